#!/usr/bin/env bash
# AO family benchmarks (SPEC 8.3, issue 4), trimmed to ~2.5 minutes on an H200
# (each 1080p run: ~1.2 s of frames + ~1 s start-up; the raster G-buffer alone
# costs ~4.5 ms/frame there). 52 runs:
#   atrium:     every variant at 8/16/24 samples, full and half resolution (36);
#   restaurant: every variant at 16 samples, half resolution (6);
#   dragon:     every variant at 16 samples, half resolution (6);
#   atrium:     the complete-chain target (8 samples, half, blur+temporal+upsample)
#               for hbao/gtao/vo, and blur-temporal-blur once (4).
# The per-pass medians of every run show each ao.* dispatch separately, so the
# chain cost of the sample sweeps is read from the same runs.
# Run from the repo root with BENCH, OUT and SCENES set by the caller.
set -euo pipefail
: "${BENCH:?set BENCH=./build/rtgi-bench}" "${OUT:?set OUT}" "${SCENES:?set SCENES}"
COMMON=(--res 1920x1080 --frames 100 --warmup 20 --no-images --set lpv=off)
# Radii by scene scale (docs/ao.md "Radius for the benchmarks"): the ~30 m atrium
# needs 1.5 for visible AO under arches and at pillar bases; the restaurant 1.0;
# the dragon on its floor keeps the default 0.5.
ATRIUM=(--scene builtin:atrium --set ao.radius=1.5)
RESTAURANT=(--scene builtin:restaurant --set ao.radius=1.0)
DRAGON=(--scene builtin:plane --scene "$SCENES/stanford-dragon/dragon.gltf")
VARIANTS=(ssao-disk ssao-sphere ssao-hemisphere vo hbao gtao)

for variant in "${VARIANTS[@]}"; do
  for samples in 8 16 24; do
    for res in full half; do
      "$BENCH" "${ATRIUM[@]}" "${COMMON[@]}" --set ao="$variant" --set ao.samples="$samples" \
        --set ao.resolution="$res" --out "$OUT/ao/atrium-$variant-$samples-$res"
    done
  done
done
for variant in "${VARIANTS[@]}"; do
  "$BENCH" "${RESTAURANT[@]}" "${COMMON[@]}" --set ao="$variant" --set ao.samples=16 --set ao.resolution=half \
    --out "$OUT/ao/restaurant-$variant-16-half"
  "$BENCH" "${DRAGON[@]}" "${COMMON[@]}" --set ao="$variant" --set ao.samples=16 --set ao.resolution=half \
    --out "$OUT/ao/dragon-$variant-16-half"
done
# Target configuration: complete chain, <= 0.15 ms at 1080p on an H100/H200.
for variant in hbao gtao vo; do
  "$BENCH" "${ATRIUM[@]}" "${COMMON[@]}" --set ao="$variant" --set ao.samples=8 --set ao.resolution=half \
    --set ao.blur=on --set ao.temporal=on --set ao.upsample=on --out "$OUT/ao/atrium-chain-$variant"
done
"$BENCH" "${ATRIUM[@]}" "${COMMON[@]}" --set ao=gtao --set ao.samples=8 --set ao.resolution=half \
  --set ao.filter_chain=blur-temporal-blur --out "$OUT/ao/atrium-chain-gtao-btb"
