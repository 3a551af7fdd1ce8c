#!/usr/bin/env bash
# LPV benchmarks (SPEC 8.3, issue 3) at 1080p on atrium, restaurant and the
# dragon on a floor: grid 8^3..256^3 (compute and the seed's raster baseline,
# same settings, same run), iterations 1..64, RSM 128^2..2048^2, rgba16f vs
# rgba32f, and the "full LPV" target (32^3, 8 iterations, occlusion + bounce,
# specular, RSM 256^2) for both paths. Cells are auto-fitted (lpv.cell=0), so
# every grid covers the scene. 75 runs, ~3 minutes on an H100. Run from the repo root with BENCH, OUT and
# SCENES set by the caller.
set -euo pipefail
: "${BENCH:?set BENCH=./build/rtgi-bench}" "${OUT:?set OUT}" "${SCENES:?set SCENES}"
COMMON=(--res 1920x1080 --frames 100 --warmup 20 --no-images --set lpv=on --set ao=off --set ssr=off)
declare -A SCENE_ARGS=(
  [atrium]="--scene builtin:atrium"
  [restaurant]="--scene builtin:restaurant"
  [dragon]="--scene builtin:plane --scene $SCENES/stanford-dragon/dragon.gltf"
)
run() {  # run NAME SETTINGS...
  local name=$1
  shift
  local sets=()
  for kv in "$@"; do sets+=(--set "$kv"); done
  "$BENCH" "${sargs[@]}" "${COMMON[@]}" "${sets[@]}" --out "$OUT/lpv/$scene-$name"
}
for scene in atrium restaurant dragon; do
  # shellcheck disable=SC2086
  read -r -a sargs <<< "${SCENE_ARGS[$scene]}"
  # Grid sweep, compute vs raster; 256^3 last (largest memory). Atrium and the dragon
  # only: the per-cell costs do not depend on the scene, the injection contention
  # (8^3) is largest on the compact dragon (docs/lpv.md, "Costs").
  if [[ $scene != restaurant ]]; then
    for grid in 8 16 32 64 128 256; do
      for path in compute raster; do
        run "grid$grid-$path" lpv.grid=$grid lpv.path=$path lpv.specular=off
      done
    done
  fi
  for it in 1 2 4 16 32 64; do
    run "iter$it" lpv.iterations=$it lpv.specular=off
  done
  for rsm in 128 512 1024 2048; do
    run "rsm$rsm" lpv.rsm=$rsm lpv.specular=off
  done
  run "fp32" lpv.format=rgba32f lpv.specular=off
  # Target: full LPV <= 0.25 ms GPU total on an H100/H200 (seed: 4.83 ms on a GTX 1050).
  for path in compute raster; do
    run "full-$path" lpv.grid=32 lpv.iterations=8 lpv.occlusion=on lpv.bounce=on lpv.specular=on \
      lpv.rsm=256 lpv.path=$path
  done
  # The same with the temporal blend (one more full-volume pass).
  run "full-temporal" lpv.grid=32 lpv.iterations=8 lpv.occlusion=on lpv.bounce=on lpv.specular=on \
    lpv.rsm=256 lpv.temporal=0.5
done
