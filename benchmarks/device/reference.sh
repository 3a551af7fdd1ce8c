#!/usr/bin/env bash
# Ray-traced reference benchmarks (issue 5, SPEC 7): rays/s of the AO
# reference on atrium, restaurant and the dragon on a floor at 1080p, time to
# 256 AO rays per pixel (target <= 10 s on an H100/H200), and a converged
# path-traced indirect reference of the Cornell box. The reference traces
# once (frame 0) and stays valid for the static camera, so few frames are
# enough; rays/s, seconds and spp land in results.json "stats"
# (ref.ao.rays_per_s, ref.ao.seconds, ref.path.rays_per_s, ...).
# Run from the repo root with BENCH, OUT and SCENES set.
set -euo pipefail
BENCH=${BENCH:-./build/rtgi-bench}
OUT=${OUT:-out}
SCENES=${SCENES:-../shared/scenes}
COMMON=(--res 1920x1080 --frames 2 --warmup 0 --no-images --set reference.cache=off)

run() {
  local name=$1; shift
  "$BENCH" "$@" "${COMMON[@]}" --out "$OUT/reference/$name"
}

for ao in 256; do
  run "ao-atrium-$ao" --scene builtin:atrium --set reference=ao --set reference.spp=$ao --set ao.radius=1.0
  run "ao-restaurant-$ao" --scene builtin:restaurant --set reference=ao --set reference.spp=$ao --set ao.radius=0.5
  run "ao-dragon-$ao" --scene builtin:plane --scene "$SCENES/stanford-dragon/dragon.gltf" \
      --set reference=ao --set reference.spp=$ao --set ao.radius=0.5
done
# Path-traced references: rays/s of a full path tracer and the converged indirect Cornell image.
run "indirect-cornell-1024" --scene builtin:cornell --set reference=indirect --set reference.spp=1024
run "full-atrium-64" --scene builtin:atrium --set reference=full --set reference.spp=64
run "full-dragon-64" --scene builtin:plane --scene "$SCENES/stanford-dragon/dragon.gltf" \
    --set reference=full --set reference.spp=64
# The Cornell indirect image itself (PNG + PFM), at 1080p.
"$BENCH" --scene builtin:cornell --res 1920x1080 --frames 1 --warmup 0 --set reference=indirect \
    --set reference.spp=1024 --set reference.cache=off --out "$OUT/reference/indirect-cornell-image"
