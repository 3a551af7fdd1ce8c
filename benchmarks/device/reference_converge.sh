#!/usr/bin/env bash
# Issue 21 on the device: time for the full path-traced reference to reach
# noise <= 0.2 x the frame's error at 1080p (atrium court, restaurant
# entrance, dragon front; the main job's defaults), with the caustic paths
# regularized (default) or as they are (CAUSTICS=on); and the bias of the
# regularization against a long unregularized run (BIAS=1: atrium court at
# 480x270, 16384 unregularized paths against 4096 regularized ones, both
# reference images written for comparison).
#   BENCH=... SCENES=... OUT=... CAUSTICS=regularized BUDGET=120 benchmarks/device/reference_converge.sh
set -uo pipefail
BENCH=${BENCH:-./build/rtgi-bench}
OUT=${OUT:-out}
SCENES=${SCENES:-../shared/scenes}
CAUSTICS=${CAUSTICS:-regularized}
BUDGET=${BUDGET:-120}
VIEWS=${VIEWS:-"court entrance dragon"}
run() {
  local name=$1; shift
  "$BENCH" "$@" --res 1920x1080 --frames 20 --warmup 10 --no-images --set reference=full \
      --set reference.target_noise=0.2 --set reference.time_budget="$BUDGET" --set reference.caustics="$CAUSTICS" \
      --set reference.cache=off --reference --out "$OUT/converge/$CAUSTICS-$name" 2>&1 | grep -v '^ ' | tail -n 4
}
for v in $VIEWS; do
  case $v in
    court) run court --scene builtin:atrium --set view=court --set ao.radius=1.0 ;;
    entrance) run entrance --scene builtin:restaurant --set view=entrance --set ao.radius=0.3 ;;
    dragon) run dragon --scene builtin:plane --scene "$SCENES/stanford-dragon/dragon.gltf" --set view=front --set ao.radius=0.4 ;;
  esac
done
if [ "${BIAS:-0}" = 1 ]; then
  for c in on:16384 regularized:4096 off:4096; do
    "$BENCH" --scene builtin:atrium --set view=court --res 480x270 --frames 1 --warmup 0 --set reference=full \
        --set reference.spp="${c#*:}" --set reference.caustics="${c%%:*}" --set reference.cache=off --reference \
        --out "$OUT/bias/${c%%:*}" 2>&1 | grep -v '^ ' | tail -n 2
  done
fi
