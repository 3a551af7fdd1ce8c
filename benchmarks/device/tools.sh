#!/usr/bin/env bash
# Shipped sweeps on the NVIDIA machine (run from the repo root):
#   BENCH=./build/rtgi-bench OUT=/tmp/out SCENES=/path/to/shared/scenes benchmarks/device/tools.sh [sweep ...]
# Each sweep resumes into $OUT/sweeps/<name>; report.py then writes
# $OUT/sweeps/report/report.md and the plots (copy them to docs/RESULTS.md and
# docs/results/). Default set (~4 minutes on an H100: 108 + 18 + 28
# configurations of 120 frames): ao-samples, lpv-grid, full-frame; name others
# (ao-resolution ao-radius-mode lpv-iterations lpv-rsm lpv-raster-vs-compute
# ssr-steps stress) as arguments. ci-tiny is for CI.
set -euo pipefail
: "${BENCH:?set BENCH=path/to/rtgi-bench}" "${OUT:?set OUT=output directory}" "${SCENES:?set SCENES=shared scenes directory}"
export SCENES
sweeps=("$@")
if [ ${#sweeps[@]} -eq 0 ]; then
  sweeps=(ao-samples lpv-grid full-frame)
fi
dirs=()
for s in "${sweeps[@]}"; do
  # A sweep with configurations this build cannot run yet exits 1; the others still count.
  "$BENCH" --sweep "benchmarks/sweeps/$s.json" --out "$OUT/sweeps/$s" || echo "tools.sh: $s: some configurations failed" >&2
  dirs+=("$OUT/sweeps/$s")
done
/usr/bin/python3 benchmarks/report.py "${dirs[@]}" --out "$OUT/sweeps/report" --title "rtgi sweeps ($(git rev-parse --short HEAD 2>/dev/null || echo unknown))"
