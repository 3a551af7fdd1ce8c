#!/usr/bin/env bash
# SSR: each tracer x steps at 1080p on atrium, restaurant and the Stanford
# dragon on a floor, all with a glossy floor (floor.roughness=0.1); LPV and AO
# off so the ssr.* rows are SSR alone. Then the "full SSR" target
# configuration (SPEC: trace + resolve + blur + temporal + shade <= 0.15 ms).
set -u
common=(--res 1920x1080 --frames 100 --warmup 20 --no-images --set floor.roughness=0.1 --set lpv=off --set ao=off)
declare -A scene=(
    [atrium]="--scene builtin:atrium"
    [restaurant]="--scene builtin:restaurant"
    [dragon]="--scene builtin:plane --scene $SCENES/stanford-dragon/dragon.gltf"
)
for name in atrium restaurant dragon; do
    for tracer in linear dda hiz; do
        for steps in 16 32 64 128; do
            # shellcheck disable=SC2086
            $BENCH ${scene[$name]} "${common[@]}" --set ssr=$tracer --set ssr.steps=$steps \
                --out "$OUT/ssr/$name-$tracer-$steps"
        done
    done
done
# Full SSR target: the default half-resolution chain with the Hi-Z tracer, 64 steps.
$BENCH --scene builtin:atrium "${common[@]}" --set ssr=hiz --set ssr.steps=64 --out "$OUT/ssr/full-atrium-hiz-64"
$BENCH --scene builtin:atrium "${common[@]}" --set ssr=linear --set ssr.steps=64 --out "$OUT/ssr/full-atrium-linear-64"
