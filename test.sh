#!/usr/bin/env bash
# The tests: install missing packages, build, run every test through ctest
# (unit tier without GL, GPU tier on EGL: Mesa llvmpipe without a GPU).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/scripts/common.sh"
install_missing_packages
build_rtgi
cd "$ROOT/build"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "$@"
