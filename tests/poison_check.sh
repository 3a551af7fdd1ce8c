#!/usr/bin/env bash
# Read-before-write check: every new GL buffer starts as 0xA5 bytes
# (RTGI_POISON=1), as a driver that recycles memory would leave it; a pass
# that reads a buffer before writing it then fails --check (NaN/Inf) or its
# own overflow checks, on llvmpipe too (docs/STABILITY.md).
set -u
bench=$1 out=$2
mkdir -p "$out"
fail=0
for scene in builtin:cornell builtin:atrium builtin:gallery; do
  for path in compute hardware; do
    if ! RTGI_POISON=1 "$bench" --scene "$scene" --res 48x32 --frames 3 --warmup 1 --check --no-images \
        --set raster.path=$path --out "$out/${scene#builtin:}-$path" >"$out/${scene#builtin:}-$path.log" 2>&1; then
      echo "FAILED: $scene raster.path=$path (log: $out/${scene#builtin:}-$path.log)"
      tail -3 "$out/${scene#builtin:}-$path.log"
      fail=1
    fi
  done
done
exit $fail
