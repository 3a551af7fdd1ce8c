#!/usr/bin/env bash
# The main job: install missing packages, build, render the default scene
# (builtin:atrium) headless, print the per-pass timing table, write images
# and results to ./out. Extra arguments go to rtgi-bench.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/scripts/common.sh"
install_missing_packages
build_rtgi
cd "$ROOT"
exec ./build/rtgi-bench --scene builtin:atrium --res 1280x720 --frames 100 --warmup 20 --out out "$@"
