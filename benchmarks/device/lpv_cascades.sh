#!/usr/bin/env bash
# Issue 12: the lpv-cascades sweep (cascades 1-4 x grid 16/24/32 x iterations
# 4-32 on the atrium court and arcade, cornell and the dragon, 1080p, against
# the one-bounce Lambert reference) and its report (Pareto plots of error
# against LPV time). Run from the repo root with BENCH, OUT and SCENES set by
# the caller, e.g.
#   BENCH=./build/rtgi-bench OUT=$OUT SCENES=../shared/scenes benchmarks/device/lpv_cascades.sh
# 192 runs plus 4 references (1080p, 256 paths, cached in ./rtgi-cache).
set -euo pipefail
: "${BENCH:?set BENCH=./build/rtgi-bench}" "${OUT:?set OUT}" "${SCENES:?set SCENES}"
export SCENES
"$BENCH" --sweep benchmarks/sweeps/lpv-cascades.json \
  --no-images --out "$OUT/lpv-cascades"
python3 benchmarks/report.py "$OUT/lpv-cascades"
