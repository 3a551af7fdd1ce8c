#!/usr/bin/env bash
# Issue 22, fourth pass (docs/RESULTS.md "GI suite, fourth pass"): the GI suite
# (benchmarks/sweeps/gi-suite.json, 15 views, 480x270, converged full references, one shared
# reference cache) with one axis of LPV cases, the defaults first. CASES (a JSON list of
# settings objects) replaces the default list below; REFCACHE (default $OUT/refcache) keeps the
# references for a later call on the same machine, TIME_BUDGET (default 40) caps each reference's
# seconds, NAME (default gi) names the output folder. Run from the repo root:
#   BENCH=./build/rtgi-bench OUT=/tmp/out SCENES=../shared/scenes benchmarks/device/gi_suite_fourth.sh
# then python3 benchmarks/report.py "$OUT/gi" (the "GI suite" tables: one row per case, in axis order).
# The propagation variants of the table that are not settings (walls only, min(1 - beta, tau)) were
# run as shader edits of compute/lpv/propagate.glsl loaded through RTGI_DATA_DIR (docs/lpv.md).
set -euo pipefail
: "${BENCH:?set BENCH=./build/rtgi-bench}" "${OUT:?set OUT}" "${SCENES:?set SCENES}"
NAME=${NAME:-gi}
REFCACHE=${REFCACHE:-$OUT/refcache}
mkdir -p "$OUT/$NAME" "$REFCACHE"
python3 - "$OUT/$NAME/sweep.json" "$REFCACHE" "${CASES:-}" "${TIME_BUDGET:-40}" "${RESOLUTIONS:-}" <<'PY'
import json, sys
s = json.load(open("benchmarks/sweeps/gi-suite.json"))
s["name"] = "gi-fourth"
s["base"]["reference.cache"] = sys.argv[2]
s["base"]["reference.time_budget"] = float(sys.argv[4])
if sys.argv[5]:
    s["resolutions"] = json.loads(sys.argv[5])
s["axes"] = [json.loads(sys.argv[3]) if sys.argv[3] else [
    {},
    {"lpv.apply_resolution": "half"},
    {"lpv.blocking": "visibility"},
    {"lpv.blocking": "visibility", "lpv.visibility_exponent": 3},
    {"lpv.blocking": "visibility", "lpv.iterations": 16},
    {"lpv.blocking": "visibility", "lpv.iterations": 16, "lpv.sh_order": 2},
    {"lpv.iterations": 16},
]]
json.dump(s, open(sys.argv[1], "w"), indent=2)
PY
SCENES="$SCENES" "$BENCH" --sweep "$OUT/$NAME/sweep.json" --no-images --out "$OUT/$NAME"
