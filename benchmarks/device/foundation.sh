#!/usr/bin/env bash
# Foundation passes (G-buffer, shadow, direct, compose) at 1080p on the
# built-in scenes and the Stanford dragon on a floor, everything else off.
set -u
common=(--res 1920x1080 --frames 100 --warmup 20 --no-images --set lpv=off --set ao=off --set ssr=off)
for s in atrium restaurant cornell; do
    $BENCH --scene builtin:$s "${common[@]}" --out "$OUT/foundation/$s"
done
$BENCH --scene builtin:plane --scene "$SCENES/stanford-dragon/dragon.gltf" "${common[@]}" --out "$OUT/foundation/dragon"
# Default configuration of the main job (whatever the frame needs) at 1080p.
$BENCH --scene builtin:atrium --res 1920x1080 --frames 100 --warmup 20 --out "$OUT/foundation/atrium-default"
