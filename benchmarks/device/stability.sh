#!/usr/bin/env bash
# Issue 9 on the NVIDIA machine (run from the repo root): the stress sweep
# (benchmarks/sweeps/stress.json, check on: 3 scenes x ~60 extremes, 12 frames
# each, 320x180 except the resolution axis) and a summary of every
# configuration that failed or reported NaN/Inf (docs/STABILITY.md).
#   BENCH=./build/rtgi-bench OUT=/tmp/out benchmarks/device/stability.sh
set -uo pipefail
: "${BENCH:?set BENCH=path/to/rtgi-bench}" "${OUT:?set OUT=output directory}"
dir="$OUT/stability/stress"
"$BENCH" --sweep benchmarks/sweeps/stress.json --no-images --out "$dir"
rc=$?
/usr/bin/python3 - "$dir/results.jsonl" <<'PY'
import json, sys
bad = total = 0
for line in open(sys.argv[1]):
    if not line.strip():
        continue
    r = json.loads(line)
    total += 1
    nf = r.get("check", {}).get("non_finite")
    if "failed" in r or nf is None or nf > 0:
        bad += 1
        print("FAIL", r.get("sweep", {}).get("id"), r.get("failed", ""), "non_finite =", nf)
print(f"stability: {total - bad} of {total} configurations finite")
PY
exit $rc
