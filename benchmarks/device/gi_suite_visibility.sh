#!/usr/bin/env bash
# Issue 22, visibility remedies (docs/lpv.md, "Visibility moments", "Sky visibility"): the GI
# suite (benchmarks/sweeps/gi-suite.json, 15 views, 480x270, converged full references) with
# today's LPV defaults and with the candidate defaults, same run, same cached references, plus
# the per-pass LPV cost of both at 1080p on the restaurant, the atrium and the dragon.
# Cases (an explicit axis added to the suite):
#   today:     lpv.lookup=geometry   lpv.sky=ambient    lpv.blocking=oriented
#   visibility lpv.lookup=visibility lpv.sky=visibility lpv.blocking=oriented
#   +blocking  lpv.lookup=visibility lpv.sky=visibility lpv.blocking=visibility
# Run from the repo root with BENCH, OUT and SCENES set by the caller.
set -euo pipefail
: "${BENCH:?set BENCH=./build/rtgi-bench}" "${OUT:?set OUT}" "${SCENES:?set SCENES}"
mkdir -p "$OUT/gi-suite-visibility"
SWEEP="$OUT/gi-suite-visibility/sweep.json"
python3 - "$SWEEP" <<'PY'
import json, sys
s = json.load(open("benchmarks/sweeps/gi-suite.json"))
s["name"] = "gi-suite-visibility"
s["axes"] = [[
    {"lpv.lookup": "geometry", "lpv.sky": "ambient", "lpv.blocking": "oriented"},
    {"lpv.lookup": "visibility", "lpv.sky": "visibility", "lpv.blocking": "oriented"},
    {"lpv.lookup": "visibility", "lpv.sky": "visibility", "lpv.blocking": "visibility"},
]]
json.dump(s, open(sys.argv[1], "w"), indent=2)
PY
SCENES="$SCENES" "$BENCH" --sweep "$SWEEP" --no-images --out "$OUT/gi-suite-visibility"
# Cost at 1080p (no reference): lpv.* passes, today vs candidate; lpv.visibility runs in the
# first frame only (static placement): its one-time cost is the first-frame run below.
COMMON=(--res 1920x1080 --frames 100 --warmup 20 --no-images)
for scene in restaurant atrium dragon; do
  case $scene in
    dragon) sargs=(--scene builtin:plane --scene "$SCENES/stanford-dragon/dragon.gltf") ;;
    *) sargs=(--scene "builtin:$scene") ;;
  esac
  "$BENCH" "${sargs[@]}" "${COMMON[@]}" --out "$OUT/gi-suite-visibility/cost-$scene-today"
  "$BENCH" "${sargs[@]}" "${COMMON[@]}" --set lpv.lookup=visibility --set lpv.sky=visibility \
    --out "$OUT/gi-suite-visibility/cost-$scene-visibility"
  "$BENCH" "${sargs[@]}" "${COMMON[@]}" --set lpv.lookup=visibility --set lpv.sky=visibility \
    --set lpv.blocking=visibility --out "$OUT/gi-suite-visibility/cost-$scene-visibility-blocking"
  "$BENCH" "${sargs[@]}" "${COMMON[@]}" --out "$OUT/gi-suite-visibility/cost-$scene-today-again"
  # The one-time ray pass (moments + sky visibility of both cascades): the first frame alone.
  "$BENCH" "${sargs[@]}" --res 1920x1080 --frames 1 --warmup 0 --no-images --set lpv.lookup=visibility \
    --set lpv.sky=visibility --set lpv.blocking=visibility --out "$OUT/gi-suite-visibility/cost-$scene-first-frame"
done
