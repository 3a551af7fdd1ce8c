#!/usr/bin/env bash
# AO family benchmarks (SPEC 8.3, issue 4): every variant at 8/16/24 samples,
# full and half resolution, 1080p, on atrium, restaurant and the dragon on a
# floor; plus the "complete chain" target (8 samples, half, blur+temporal+upsample).
# Run from the repo root with BENCH, OUT and SCENES set by the caller.
set -euo pipefail
: "${BENCH:?set BENCH=./build/rtgi-bench}" "${OUT:?set OUT}" "${SCENES:?set SCENES}"
COMMON=(--res 1920x1080 --frames 100 --warmup 20 --no-images)
declare -A SCENE_ARGS=(
  [atrium]="--scene builtin:atrium"
  [restaurant]="--scene builtin:restaurant"
  [dragon]="--scene builtin:plane --scene $SCENES/stanford-dragon/dragon.gltf"
)
for scene in atrium restaurant dragon; do
  # shellcheck disable=SC2086
  read -r -a sargs <<< "${SCENE_ARGS[$scene]}"
  for variant in ssao-disk ssao-sphere ssao-hemisphere vo hbao gtao; do
    for samples in 8 16 24; do
      for res in full half; do
        "$BENCH" "${sargs[@]}" "${COMMON[@]}" --set ao="$variant" --set ao.samples="$samples" \
          --set ao.resolution="$res" --set lpv=off \
          --out "$OUT/ao/$scene-$variant-$samples-$res"
      done
    done
  done
  # Target configuration: complete chain, <= 0.15 ms at 1080p on an H100/H200.
  for variant in hbao gtao vo; do
    "$BENCH" "${sargs[@]}" "${COMMON[@]}" --set ao="$variant" --set ao.samples=8 --set ao.resolution=half \
      --set ao.blur=on --set ao.temporal=on --set ao.upsample=on --set lpv=off \
      --out "$OUT/ao/$scene-chain-$variant"
  done
done
