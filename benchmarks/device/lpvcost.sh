#!/usr/bin/env bash
# Issue 24, LPV cost (branch lpvcost; docs/lpv.md "Joint cascade propagation", "Apply cost",
# "Geometry injection stride"): the frame and the LPV passes at 1080p on the atrium, the restaurant
# and the dragon, 60 frames after 20, with the defaults (joint cascade propagation, the apply's
# exact shortcuts, geometry stride 2) and each option:
#   lpv.propagate_cascades=separate  one propagation dispatch per cascade and iteration (as before)
#   lpv.geometry_stride=4            geometry injection from every 4th G-buffer pixel in x and y
# every run with profile.dispatches=on (per-dispatch sub-steps: lpv.propagate/lpv/propagate.comp,
# lpv.apply/lpv/apply.comp, lpv.inject_geometry/lpv/inject_geometry.comp) and once more without it
# (the frame total without the per-dispatch timer pairs).
# BASE=path/to/another/rtgi-bench (e.g. a build of main before this branch) runs the defaults and
# profile.dispatches=on with that binary into $OUT/lpvcost-base in the same session (same card,
# same driver); frame_table.py prints both side by side (same run names).
# GI=1 also runs the GI suite's error (benchmarks/sweeps/gi-suite.json) with lpv.geometry_stride 2
# and 4 (the joint propagation and the apply shortcuts do not change the result: tests).
# Run from the repo root with BENCH, OUT and SCENES set.
FRAMES=${FRAMES:-60}
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

P=profile.dispatches=on
suite "$BENCH" "$OUT/lpvcost" "" "$P" "$P lpv.propagate_cascades=separate" "$P lpv.geometry_stride=4" \
  "$P lpv.geometry_stride=4 lpv.propagate_cascades=separate" "lpv.geometry_stride=4"
# The base binary knows neither key: its defaults are one dispatch per cascade and stride 2.
[ -n "${BASE:-}" ] && suite "$BASE" "$OUT/lpvcost-base" "" "$P"
python3 benchmarks/device/frame_table.py "$OUT/lpvcost" ${BASE:+"$OUT/lpvcost-base"}
# Dispatch counts of the propagation (results.json "dispatches" per pass, when written).
python3 - "$OUT/lpvcost" <<'PY'
import json, pathlib, sys
for p in sorted(pathlib.Path(sys.argv[1]).glob("*/results.json")):
    doc = json.loads(p.read_text())
    for q in doc.get("passes", []):
        if q["name"] in ("lpv.propagate", "lpv.apply", "lpv.inject_geometry") and "dispatches" in q:
            print(f"{p.parent.name}: {q['name']} {q['dispatches']} dispatches")
PY
if [ -n "${GI:-}" ]; then
  mkdir -p "$OUT/gi-suite-lpvcost"
  python3 - "$OUT/gi-suite-lpvcost/sweep.json" <<'PY'
import json, sys
s = json.load(open("benchmarks/sweeps/gi-suite.json"))
s["name"] = "gi-suite-lpvcost"
s["axes"] = [[{"lpv.geometry_stride": 2}, {"lpv.geometry_stride": 4},
              {"lpv.propagate_cascades": "separate"}]]
json.dump(s, open(sys.argv[1], "w"), indent=2)
PY
  SCENES="$SCENES" "$BENCH" --sweep "$OUT/gi-suite-lpvcost/sweep.json" --no-images --out "$OUT/gi-suite-lpvcost"
fi
