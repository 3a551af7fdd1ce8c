#!/usr/bin/env bash
# CI's sanitizer job (issue 16): the loader, metrics and hardening unit tests
# built with -fsanitize=address,undefined in their own build directory
# (build-sanitize), so that a heap overflow, use after free, signed overflow,
# bad shift or invalid enum load in the code that reads untrusted files fails
# CI (-fno-sanitize-recover=all aborts on the first finding). Only the unit
# test binary is built (rtgi_core, the unit tests and rtgi-bench, which they call).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="$(nproc 2>/dev/null || echo 2)"
cmake -S "$ROOT" -B "$ROOT/build-sanitize" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRTGI_SANITIZE=ON \
      -DRTGI_BUILD_VIEWER=OFF >/dev/null
cmake --build "$ROOT/build-sanitize" -j "$jobs" --target rtgi-tests-unit
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
"$ROOT/build-sanitize/rtgi-tests-unit" \
    -tc='gltf*,hardening*,RMSE*,Relative RMSE*,SSIM*,Error heat map*,depthInteriorMask*,sweep*,settings*'
