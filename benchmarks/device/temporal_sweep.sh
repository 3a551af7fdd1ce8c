#!/usr/bin/env bash
# Temporal sweep (issue 23, docs/temporal.md "Sweeps"), sized for ~6 minutes of
# an H200 at 480x270: the temporal settings over three named paths, each run
# with a reference every 8th frame pair (every 4th on the 1 s fast pan) and
# 64 spp references, cached across runs of the same path and kind.
#   ao.temporal on/off          (reference=ao)        atrium-flythrough, atrium-fast-pan, cornell-moving-box
#   lpv.temporal 0 / 0.5 / 0.9  (reference=indirect)  atrium-flythrough, atrium-fast-pan
#   ssr.diffuse_history off/on  (reference=full)      atrium-flythrough, atrium-fast-pan
#   LPV placement: lpv.cascades=1 (scene-fit, never moves) vs 3 (camera-following, snapped to cells)
#                               (reference=indirect)  atrium-flythrough, atrium-fast-pan
# rtgi has no unsnapped camera-following volume, so "snapping off" is the
# static scene-fit volume here (docs/temporal.md).
# Each run directory holds results.json (path, temporal) and temporal.csv;
# afterwards, on a machine with matplotlib:
#   /usr/bin/python3 benchmarks/report.py "$OUT/temporal_sweep" --out "$OUT/temporal_sweep/report"
# Run from the repo root: BENCH=./build/rtgi-bench OUT=/some/dir benchmarks/device/temporal_sweep.sh
set -euo pipefail
: "${BENCH:?set BENCH=./build/rtgi-bench}" "${OUT:?set OUT}"
DIR="$OUT/temporal_sweep"
mkdir -p "$DIR"
CACHE="$DIR/reference_cache"
COMMON=(--res 480x270 --warmup 10 --no-images --reference --set reference.spp=64 --set "reference.cache=$CACHE")
START=$SECONDS

run() {  # run NAME SCENE PATH EVERY ARGS...
  local name=$1 scene=$2 path=$3 every=$4
  shift 4
  local t0=$SECONDS
  "$BENCH" --scene "builtin:$scene" --path "$path" --reference-every "$every" "${COMMON[@]}" "$@" \
    --out "$DIR/$name" > "$DIR/$name.log" 2>&1 || echo "temporal_sweep: $name failed (see $DIR/$name.log)"
  echo "temporal_sweep: $name $((SECONDS - t0)) s (total $((SECONDS - START)) s)"
}

every() { [ "$1" = atrium-fast-pan ] && echo 4 || echo 8; }

for p in atrium:atrium-flythrough atrium:atrium-fast-pan cornell:cornell-moving-box; do
  scene=${p%%:*} path=${p##*:}
  for a in on off; do
    run "$path-ao.temporal-$a" "$scene" "$path" "$(every "$path")" --set reference=ao --set ao.temporal=$a
  done
done
for path in atrium-flythrough atrium-fast-pan; do
  for t in 0 0.5 0.9; do
    run "$path-lpv.temporal-$t" atrium "$path" "$(every "$path")" --set reference=indirect --set lpv.temporal=$t
  done
  run "$path-lpv.cascades-3" atrium "$path" "$(every "$path")" --set reference=indirect --set lpv.cascades=3
  for h in off on; do
    run "$path-ssr.diffuse_history-$h" atrium "$path" "$(every "$path")" --set reference=full \
      --set ssr=linear --set ssr.diffuse_history=$h
  done
done
# The object's disocclusion with the PNG sequence (and path.mp4 where ffmpeg exists) for the eye.
run "cornell-moving-box-frames" cornell cornell-moving-box 8 --set reference=ao --path-frames
echo "temporal_sweep: done in $((SECONDS - START)) s; report: /usr/bin/python3 benchmarks/report.py $DIR --out $DIR/report"
