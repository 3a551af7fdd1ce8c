#!/usr/bin/env bash
# SSR: each tracer x steps at 1080p on atrium, restaurant and the Stanford
# dragon on a floor, all with a glossy floor (floor.roughness=0.1); LPV and AO
# off so the ssr.* rows are SSR alone. Every run is the full default chain
# (half-resolution trace + resolve + shared blur / temporal / upsample + shade),
# so the "full SSR <= 0.15 ms" target is read off the same rows (64 steps).
# 27 runs of 120 frames: about 1.5 min on an H200 (each run >= 1 s + ~1 s
# start-up; the raster G-buffer alone is ~4.5 ms/frame there).
# Run from the repo root with BENCH, OUT and SCENES set by the caller.
set -euo pipefail
: "${BENCH:?set BENCH=./build/rtgi-bench}" "${OUT:?set OUT}" "${SCENES:?set SCENES}"
common=(--res 1920x1080 --frames 100 --warmup 20 --no-images --set floor.roughness=0.1 --set lpv=off --set ao=off)
declare -A scene=(
    [atrium]="--scene builtin:atrium"
    [restaurant]="--scene builtin:restaurant"
    [dragon]="--scene builtin:plane --scene $SCENES/stanford-dragon/dragon.gltf"
)
for name in atrium restaurant dragon; do
    read -r -a sargs <<< "${scene[$name]}"
    for tracer in linear dda hiz; do
        for steps in 32 64 128; do
            "$BENCH" "${sargs[@]}" "${common[@]}" --set ssr="$tracer" --set ssr.steps="$steps" \
                --out "$OUT/ssr/$name-$tracer-$steps"
        done
    done
done
