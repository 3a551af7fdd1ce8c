#!/usr/bin/env bash
# Runs the benchmark scripts of the given families (default: all) on the GPU
# machine and packs every results.json into $OUT/results.tgz.
#   BENCH=path/to/rtgi-bench SCENES=path/to/shared/scenes OUT=dir bash benchmarks/device/run_all.sh [family...]
set -u
: "${BENCH:?}" "${SCENES:?}" "${OUT:?}"
export BENCH SCENES
RAW="${RAW:-/tmp/rtgi-device-results}"
mkdir -p "$RAW"
families=("$@")
[ ${#families[@]} -eq 0 ] && families=(foundation lpv ao ssr reference stability lights raster)
for f in "${families[@]}"; do
    script="benchmarks/device/$f.sh"
    [ -f "$script" ] || { echo "skip $f (no $script)"; continue; }
    start=$(date +%s)
    OUT="$RAW" bash "$script" >"$RAW/$f.log" 2>&1
    echo "$f: exit $? in $(( $(date +%s) - start )) s"
    tail -3 "$RAW/$f.log"
done
tar czf "$OUT/results.tgz" -C "$RAW" .
