#!/usr/bin/env bash
# Issue 24 deliverable 3, the scaling table: the default frame and its passes at 720p, 1080p,
# 1440p and 2160p on the atrium, the restaurant and the dragon, with both raster paths
# (raster.path=hardware|compute), and over triangle count with the 5 M-triangle dragon crowd
# (50 dragons, benchmarks/scenes/dragon_crowd.py, generated under $OUT and removed) at 1080p
# and 2160p. Medians of FRAMES (60) frames after 20. Run from the repo root with BENCH, OUT and
# SCENES set; then python3 benchmarks/device/scaling_table.py "$OUT/scaling".
set -u
: "${BENCH:?set BENCH=./build/rtgi-bench}" "${OUT:?set OUT}" "${SCENES:?set SCENES}"
dir="$OUT/scaling"
mkdir -p "$dir"
common=(--frames "${FRAMES:-60}" --warmup 20 --no-images)
run() {  # name, args...
  local name=$1; shift
  "$BENCH" "$@" "${common[@]}" --out "$dir/$name" >"$dir/$name.log" 2>&1 || echo "FAILED $name"
}
for res in 1280x720 1920x1080 2560x1440 3840x2160; do
  for path in hardware compute; do
    run "atrium-$res-$path" --scene builtin:atrium --res "$res" --set raster.path="$path"
    run "restaurant-$res-$path" --scene builtin:restaurant --res "$res" --set raster.path="$path"
    run "dragon-$res-$path" --scene builtin:plane --scene "$SCENES/stanford-dragon/dragon.gltf" --res "$res" \
      --set raster.path="$path"
  done
done
crowd="$dir/dragon-crowd-50.gltf"
python3 benchmarks/scenes/dragon_crowd.py "$SCENES" "$crowd" 50
for res in 1920x1080 3840x2160; do
  for path in hardware compute; do
    run "crowd50-$res-$path" --scene builtin:plane --scene "$crowd" --res "$res" --set raster.path="$path"
  done
done
rm -f "$crowd"
