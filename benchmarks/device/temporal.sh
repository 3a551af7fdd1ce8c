#!/usr/bin/env bash
# Temporal error on the named paths (issue 23, docs/temporal.md): every path
# at 1280x720 with a reference per frame pair every 4 frames (and around the
# gallery's step events), and the sweep of the temporal blend factors and
# the LPV's cascades over the atrium fly-through and the fast pan. Each
# result directory holds results.json ("path", "temporal") and temporal.csv.
# Run from the repo root with BENCH and OUT set by the caller. Not run by
# run_all.sh (references per frame: tens of minutes on an H100).
set -euo pipefail
: "${BENCH:?set BENCH=./build/rtgi-bench}" "${OUT:?set OUT}"
COMMON=(--res 1280x720 --warmup 20 --no-images --reference --reference-every 4 --set reference.spp=256)

# Every named path with the default configuration: the error, flicker, lag and per-pass times per frame.
for p in atrium:atrium-flythrough atrium:atrium-sun-sweep atrium:atrium-fast-pan restaurant:restaurant-walk \
         gallery:gallery-lamp-switch cornell:cornell-moving-box; do
  scene=${p%%:*} path=${p##*:}
  "$BENCH" --scene "builtin:$scene" --path "$path" "${COMMON[@]}" --out "$OUT/temporal/$path"
  # The indirect light too (the LPV's temporal behaviour; reference=indirect).
  "$BENCH" --scene "builtin:$scene" --path "$path" "${COMMON[@]}" --set reference=indirect \
    --out "$OUT/temporal/$path-indirect"
done

# Blend factors: AO history (ao.temporal on/off), LPV temporal blend, cascades.
for path in atrium-flythrough atrium-fast-pan; do
  for t in 0 0.5 0.8 0.9 0.95; do
    "$BENCH" --scene builtin:atrium --path "$path" "${COMMON[@]}" --set reference=indirect --set lpv.temporal="$t" \
      --out "$OUT/temporal/sweep-$path-lpv.temporal-$t"
  done
  for c in 1 2 3; do
    "$BENCH" --scene builtin:atrium --path "$path" "${COMMON[@]}" --set reference=indirect --set lpv.cascades="$c" \
      --out "$OUT/temporal/sweep-$path-lpv.cascades-$c"
  done
  for a in on off; do
    "$BENCH" --scene builtin:atrium --path "$path" "${COMMON[@]}" --set ao.temporal="$a" \
      --out "$OUT/temporal/sweep-$path-ao.temporal-$a"
  done
done
# The light switch's lag with and without LPV blending.
for t in 0 0.5 0.9; do
  "$BENCH" --scene builtin:gallery --path gallery-lamp-switch "${COMMON[@]}" --reference-every 1 \
    --set reference=indirect --set lpv.temporal="$t" --out "$OUT/temporal/sweep-gallery-lpv.temporal-$t"
done
