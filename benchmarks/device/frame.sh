#!/usr/bin/env bash
# The frame budget of issue 24: the main job's frame at 1080p (defaults,
# 100 frames after 20) on the atrium, the restaurant and the dragon, plus
# variants that attribute the cost (LPV, AO, SSR off; hardware raster path),
# and builtin:gallery with 16 / 64 generated point lights.
# BASE=path/to/another/rtgi-bench runs the same list with that binary into
# $OUT/frame-base for a same-run comparison.
# Run from the repo root with BENCH, OUT and SCENES set.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

frame_suite() {  # binary, out dir, extra variant: the attribution variants and the gallery with point lights
  local bin=$1 dir=$2
  suite "$bin" "$dir" "" "lpv=off" "ao=off" "ssr=off" "raster.path=hardware" ${3:+"$3"}
  for n in 16 64; do
    python3 benchmarks/device/point_lights.py "$n" "$dir/points$n.gltf"
    one "$bin" "$dir" "gallery-points$n" --scene builtin:gallery --scene "$dir/points$n.gltf"
  done
}

# shadow.cache=off: the frame of a moving sun (the shadow map redrawn every frame).
frame_suite "$BENCH" "$OUT/frame" "shadow.cache=off"
[ -n "${BASE:-}" ] && frame_suite "$BASE" "$OUT/frame-base"
python3 benchmarks/device/frame_table.py "$OUT/frame" ${BASE:+"$OUT/frame-base"}
