#!/usr/bin/env bash
# Shared by run.sh and test.sh: install missing Debian packages (apt-get
# update first), then configure and build rtgi in ./build.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PACKAGES=(cmake g++ ninja-build pkg-config python3 python3-glad libglfw3-dev libglm-dev libtinygltf-dev libstb-dev
          nlohmann-json3-dev libegl-dev libegl1 libegl-mesa0 libgl1-mesa-dri doctest-dev xvfb xauth
          python3-matplotlib python3-numpy libtinyexr-dev zlib1g-dev libimgui-dev
          pybind11-dev python3-dev python3-pytest)

install_missing_packages() {
    local missing=()
    for p in "${PACKAGES[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    local sudo=""
    if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
    echo "rtgi: installing missing packages: ${missing[*]}" >&2
    $sudo apt-get update -q
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
}

build_rtgi() {
    local jobs
    jobs="$(nproc 2>/dev/null || echo 2)"
    cmake -S "$ROOT" -B "$ROOT/build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$ROOT/build" -j "$jobs"
}
