#!/usr/bin/env bash
# The frame budget of issue 24: the main job's frame at 1080p (defaults,
# 100 frames after 20) on the atrium, the restaurant and the dragon, plus
# variants that attribute the cost (LPV, AO, SSR off; hardware raster path),
# and builtin:gallery with 16 / 64 generated point lights.
# BASE=path/to/another/rtgi-bench runs the same list with that binary into
# $OUT/frame-base for a same-run comparison.
# Run from the repo root with BENCH, OUT and SCENES set.
set -uo pipefail
BENCH=${BENCH:-./build/rtgi-bench}
OUT=${OUT:-out}
SCENES=${SCENES:-../shared/scenes}
COMMON=(--res ${RES:-1920x1080} --frames ${FRAMES:-100} --warmup 20 --no-images)
DRAGON=(--scene builtin:plane --scene "$SCENES/stanford-dragon/dragon.gltf")

one() {  # binary, out dir, name, args...
  local bin=$1 dir=$2 name=$3; shift 3
  "$bin" "$@" "${COMMON[@]}" --out "$dir/$name" >"$dir/$name.log" 2>&1 || echo "FAILED $name ($bin)"
}

suite() {
  local bin=$1 dir=$2
  mkdir -p "$dir"
  local extra=${3:-}
  for v in "" "lpv=off" "ao=off" "ssr=off" "raster.path=hardware" $extra; do
    local tag=${v:-defaults}; tag=${tag//=/-}
    local set=(); [ -n "$v" ] && set=(--set "$v")
    one "$bin" "$dir" "atrium-$tag" --scene builtin:atrium "${set[@]}"
    one "$bin" "$dir" "restaurant-$tag" --scene builtin:restaurant "${set[@]}"
    one "$bin" "$dir" "dragon-$tag" "${DRAGON[@]}" "${set[@]}"
  done
  for n in 16 64; do
    python3 benchmarks/device/point_lights.py "$n" "$dir/points$n.gltf"
    one "$bin" "$dir" "gallery-points$n" --scene builtin:gallery --scene "$dir/points$n.gltf"
  done
}

# shadow.cache=off: the frame of a moving sun (the shadow map redrawn every frame).
suite "$BENCH" "$OUT/frame" "shadow.cache=off"
[ -n "${BASE:-}" ] && suite "$BASE" "$OUT/frame-base"
python3 benchmarks/device/frame_table.py "$OUT/frame" ${BASE:+"$OUT/frame-base"}
