#!/usr/bin/env bash
# Issue 22, third pass (docs/lpv.md, "Leaks, third pass"): the GI suite
# (benchmarks/sweeps/gi-suite.json, 15 views, 480x270, converged full references)
# with the defaults (main's, unchanged on this branch) beside the third pass's leak remedies,
# together and each alone, same run, same cached references, plus the per-pass LPV cost at 1080p.
# Cases (an explicit axis added to the suite; everything else the global defaults):
#   defaults:  lpv.blocking=oriented   lpv.visibility_exponent=1   (main at 98a52a4)
#   both:      lpv.blocking=visibility lpv.visibility_exponent=3   (traced face openness in the
#              propagation, the stopped flux reflected; DDGI's cubed Chebyshev lookup: the closed
#              room < 1 %, but the restaurant entrance below 0 on llvmpipe)
#   face:      lpv.blocking=visibility lpv.visibility_exponent=1
#   e3:        lpv.blocking=oriented   lpv.visibility_exponent=3
# Run from the repo root with BENCH, OUT and SCENES set by the caller, e.g.
#   BENCH=./build/rtgi-bench OUT=/tmp/out SCENES=../shared/scenes benchmarks/device/gi_suite_next.sh
# then: python3 benchmarks/report.py "$OUT/gi-suite-next" (the "GI suite" table, held-out views apart).
set -euo pipefail
: "${BENCH:?set BENCH=./build/rtgi-bench}" "${OUT:?set OUT}" "${SCENES:?set SCENES}"
mkdir -p "$OUT/gi-suite-next"
SWEEP="$OUT/gi-suite-next/sweep.json"
python3 - "$SWEEP" <<'PY'
import json, sys
s = json.load(open("benchmarks/sweeps/gi-suite.json"))
s["name"] = "gi-suite-next"
s["axes"] = [[
    {"lpv.blocking": "oriented", "lpv.visibility_exponent": 1},
    {"lpv.blocking": "visibility", "lpv.visibility_exponent": 3},
    {"lpv.blocking": "visibility", "lpv.visibility_exponent": 1},
    {"lpv.blocking": "oriented", "lpv.visibility_exponent": 3},
]]
json.dump(s, open(sys.argv[1], "w"), indent=2)
PY
SCENES="$SCENES" "$BENCH" --sweep "$SWEEP" --no-images --out "$OUT/gi-suite-next"
# Cost at 1080p (no reference): lpv.* passes, the defaults vs both remedies; lpv.visibility
# runs in the first frame only (static placement): its one-time cost is the first-frame run.
COMMON=(--res 1920x1080 --frames 100 --warmup 20 --no-images)
NEXT=(--set lpv.blocking=visibility --set lpv.visibility_exponent=3)
for scene in restaurant atrium dragon; do
  case $scene in
    dragon) sargs=(--scene builtin:plane --scene "$SCENES/stanford-dragon/dragon.gltf") ;;
    *) sargs=(--scene "builtin:$scene") ;;
  esac
  "$BENCH" "${sargs[@]}" "${COMMON[@]}" --out "$OUT/gi-suite-next/cost-$scene-defaults"
  "$BENCH" "${sargs[@]}" "${COMMON[@]}" "${NEXT[@]}" --out "$OUT/gi-suite-next/cost-$scene-both"
  "$BENCH" "${sargs[@]}" "${COMMON[@]}" --out "$OUT/gi-suite-next/cost-$scene-defaults-again"
  "$BENCH" "${sargs[@]}" --res 1920x1080 --frames 1 --warmup 0 --no-images "${NEXT[@]}" \
    --out "$OUT/gi-suite-next/cost-$scene-both-first-frame"
done
