#!/usr/bin/env bash
# Issue 24, LPV passes (branch lpvfast): the frame and the LPV passes at 1080p with the defaults
# on the atrium, the restaurant and the dragon, with lpv.apply_resolution=half against the default
# full, lpv.fuse=2 (two propagation iterations per dispatch) against the default 1, each also with
# profile.dispatches=on (per-dispatch sub-steps: lpv.apply/lpv/apply.comp, lpv.apply/lpv/upsample.comp,
# lpv.propagate/lpv/propagate.comp, lpv.propagate/lpv/propagate_fused.comp), and lpv=off.
# BASE=path/to/another/rtgi-bench (e.g. a build of commit 70f20d1 or of main) runs the same list
# with that binary into $OUT/lpvfast-base in the same session (same card, same driver) for the
# comparison; frame_table.py prints both side by side.
# GI=1 also runs the GI suite's error with both apply resolutions (below).
# Run from the repo root with BENCH, OUT and SCENES set.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

suite "$BENCH" "$OUT/lpvfast" "" "lpv.apply_resolution=half" "lpv.fuse=2" "lpv.apply_resolution=half lpv.fuse=2" \
  "lpv=off" "profile.dispatches=on" "profile.dispatches=on lpv.apply_resolution=half lpv.fuse=2"
# The base binary does not know lpv.apply_resolution / lpv.fuse (full-resolution apply, unfused).
[ -n "${BASE:-}" ] && suite "$BASE" "$OUT/lpvfast-base" "" "lpv=off" "profile.dispatches=on"
python3 benchmarks/device/frame_table.py "$OUT/lpvfast" ${BASE:+"$OUT/lpvfast-base"}
# GI=1: the error side on the GI suite (benchmarks/sweeps/gi-suite.json, 15 views at 480x270, converged
# full references, cached and shared by both cases): lpv.apply_resolution full vs half (and lpv.fuse 1
# vs 2, identical by construction: a check). report.py's "GI suite" tables compare the cases.
if [ -n "${GI:-}" ]; then
  mkdir -p "$OUT/gi-suite-lpvfast"
  python3 - "$OUT/gi-suite-lpvfast/sweep.json" <<'PY'
import json, sys
s = json.load(open("benchmarks/sweeps/gi-suite.json"))
s["name"] = "gi-suite-lpvfast"
s["axes"] = [[
    {"lpv.apply_resolution": "full", "lpv.fuse": 1},
    {"lpv.apply_resolution": "half", "lpv.fuse": 1},
    {"lpv.apply_resolution": "half", "lpv.fuse": 2},
]]
json.dump(s, open(sys.argv[1], "w"), indent=2)
PY
  SCENES="$SCENES" "$BENCH" --sweep "$OUT/gi-suite-lpvfast/sweep.json" --no-images --out "$OUT/gi-suite-lpvfast"
fi
