#!/usr/bin/env bash
# Issue 14 (docs/visibility.md) on the NVIDIA machine, from the repo root with
# BENCH, OUT and SCENES set (TESTS defaults to ./build/rtgi-tests-gpu):
#   1. the GPU test tier filtered to the compute rasterizer: on NVIDIA it runs
#      the 64-bit depth|id atomicMin path (GL_NV_shader_atomic_int64) and, in
#      the oracle test, the two-pass 32-bit path as well;
#   2. the sweep benchmarks/sweeps/raster-paths.json: hardware vs compute
#      rasterization, 720p/1080p/2160p, every shipped scene and the dragon;
#   3. the 32-bit path on the device (raster.atomic64=off) at 1080p, atrium;
#   4. the 5 M-triangle scene (50 dragons, generated under $OUT, never
#      committed) with both paths at 1080p and 2160p, and its GPU memory.
# About 4 minutes on an H100.
set -u
: "${BENCH:?set BENCH=./build/rtgi-bench}" "${OUT:?set OUT}" "${SCENES:?set SCENES}"
TESTS="${TESTS:-./build/rtgi-tests-gpu}"
dir="$OUT/raster"
mkdir -p "$dir"
export SCENES

RTGI_SHARED_SCENES="$SCENES" "$TESTS" -tc='visibility*' >"$dir/tests-visibility.log" 2>&1
echo "visibility tests: exit $? (log $dir/tests-visibility.log)"
grep -E "atomic64|test cases|assertions" "$dir/tests-visibility.log" | tail -5

"$BENCH" --sweep benchmarks/sweeps/raster-paths.json --no-images --out "$dir/sweep"
echo "sweep: exit $?"

common=(--frames 100 --warmup 20 --no-images --set ao=off --set ssr=off)
"$BENCH" --scene builtin:atrium --set view=court --res 1920x1080 "${common[@]}" --set raster.path=compute \
  --set raster.atomic64=off --out "$dir/atrium-1080p-compute32"

crowd="$dir/dragon-crowd-50.gltf"
python3 benchmarks/scenes/dragon_crowd.py "$SCENES" "$crowd" 50
for res in 1920x1080 3840x2160; do
  for path in hardware compute; do
    "$BENCH" --scene builtin:plane --scene "$crowd" --res "$res" "${common[@]}" --set lpv=off \
      --set raster.path="$path" --out "$dir/crowd50-$res-$path"
    echo "crowd $res $path: exit $?"
  done
done
rm -f "$crowd"
