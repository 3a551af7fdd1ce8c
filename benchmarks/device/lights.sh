#!/usr/bin/env bash
# Lights of issue 13 (docs/lights.md): cost per light type at 1080p —
# shadow.local (spot perspective map, point / area cube), lpv.rsm and
# lpv.inject for their RSMs, direct — on the original Cornell box (one
# emissive panel -> one area light) and builtin:gallery (two spot lights, one
# point light); the frame with 1, 4 and 16 point lights (builtin:gallery with
# its own lights scaled to zero, plus N point lights from a generated glTF);
# and the path tracer with and without emitter sampling on the Cornell box.
# Per-pass times land in results.json "passes"; rays/s in "stats".
# Run from the repo root with BENCH, OUT and SCENES set.
set -euo pipefail
BENCH=${BENCH:-./build/rtgi-bench}
OUT=${OUT:-out}
SCENES=${SCENES:-../shared/scenes}
CORNELL="$SCENES/cornell-box/cornell-box.gltf"
COMMON=(--res 1920x1080 --frames 100 --warmup 20 --no-images)
mkdir -p "$OUT/lights"

run() {
  local name=$1; shift
  "$BENCH" "$@" "${COMMON[@]}" --out "$OUT/lights/$name"
}

# Cost per light type, defaults (lpv=auto: on), and the shadow/RSM sizes swept.
for size in 256 512 1024; do
  run "cornell-local$size" --scene "$CORNELL" --set shadow.local_size=$size
  run "gallery-local$size" --scene builtin:gallery --set shadow.local_size=$size
done
run "cornell-lpv-off" --scene "$CORNELL" --set lpv=off
run "gallery-lpv-off" --scene builtin:gallery --set lpv=off
run "gallery-unshadowed" --scene builtin:gallery --set passes.off=shadow.local

# N point lights: a generated glTF (a 0.2 m tile in a corner of the gallery
# and N KHR_lights_punctual point lights under its ceiling) merged into the
# gallery.
GEN="$OUT/lights/generated"
mkdir -p "$GEN"
for n in 1 4 16; do
  python3 benchmarks/device/point_lights.py "$n" "$GEN/points$n.gltf"
  # The gallery's own three lights stay (they are part of every variant).
  run "points$n" --scene builtin:gallery --scene "$GEN/points$n.gltf"
  run "points$n-lpv-off" --scene builtin:gallery --scene "$GEN/points$n.gltf" --set lpv=off
done

# Path tracer on the area-lit box: 64 paths with and without emitter sampling
# against 1024 (time and error; --reference compares the run's image).
"$BENCH" --scene "$CORNELL" --res 1920x1080 --frames 1 --warmup 0 --no-images --set reference=full \
    --set reference.spp=64 --set reference.cache=off --out "$OUT/lights/cornell-ref64-nee"
"$BENCH" --scene "$CORNELL" --res 1920x1080 --frames 1 --warmup 0 --no-images --set reference=full \
    --set reference.spp=64 --set reference.light_sampling=off --set reference.cache=off \
    --out "$OUT/lights/cornell-ref64-bsdf"
