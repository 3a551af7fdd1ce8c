# Shared by the frame scripts of benchmarks/device (sourced, not run): the defaults of BENCH, OUT and
# SCENES, the run arguments (RES, FRAMES, WARMUP; a script sets its own FRAMES default before sourcing),
# the two loops every script had a copy of, and the Cornell box front view's error run (issue 26).
set -uo pipefail
BENCH=${BENCH:-./build/rtgi-bench}
OUT=${OUT:-out}
SCENES=${SCENES:-../shared/scenes}
COMMON=(--res ${RES:-1920x1080} --frames ${FRAMES:-100} --warmup ${WARMUP:-20} --no-images)
DRAGON=(--scene builtin:plane --scene "$SCENES/stanford-dragon/dragon.gltf")

one() {  # binary, out dir, name, args...: one run into dir/name (its log beside it)
  local bin=$1 dir=$2 name=$3; shift 3
  mkdir -p "$dir"
  "$bin" "$@" "${COMMON[@]}" --out "$dir/$name" >"$dir/$name.log" 2>&1 || echo "FAILED $name ($bin)"
}

suite() {  # binary, out dir, variants...: the atrium, the restaurant and the dragon per variant
  # A variant is a space-separated list of key=value settings; "" is the defaults.
  local bin=$1 dir=$2; shift 2
  mkdir -p "$dir"
  for v in "$@"; do
    local tag=${v:-defaults}; tag=${tag//=/-}; tag=${tag// /+}
    local set=(); for kv in $v; do set+=(--set "$kv"); done
    one "$bin" "$dir" "atrium-$tag" --scene builtin:atrium "${set[@]}"
    one "$bin" "$dir" "restaurant-$tag" --scene builtin:restaurant "${set[@]}"
    one "$bin" "$dir" "dragon-$tag" "${DRAGON[@]}" "${set[@]}"
  done
}

cornell_front() {  # name, args...: the original Cornell box from view=front at the acceptance's setup of issue 26
  # (480x270, 4096-path full reference, reference.split=on; cached in $REFCACHE) into $OUT/cb/name; one line of
  # its interior relative RMSE with the direct and indirect parts appended to $OUT/cb.txt.
  local n=$1; shift
  mkdir -p "$OUT/cb"
  "$BENCH" --scene "$SCENES/cornell-box/cornell-box.gltf" --set view=front --res 480x270 --frames 20 --warmup 10 \
    --no-images --reference --set reference=full --set reference.spp=4096 --set reference.split=on \
    --set reference.cache="${REFCACHE:-$OUT/cbref}" "$@" --out "$OUT/cb/$n" >"$OUT/cb/$n.log" 2>&1 || echo "FAILED $n"
  python3 - "$OUT/cb/$n/results.json" "$n" >>"$OUT/cb.txt" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); e = r["error"]; c = r["config"]
print(f'{sys.argv[2]:8s} split {c["emissive.split"]} coarse {c["lpv.coarse_iterations"]} band {c["lpv.sh_order"]} '
      f'enclosure {r.get("enclosure")} interior rel RMSE {e["interior"]["rel_rmse"]:.4f} bias {e["interior"]["bias"]:.5f} '
      f'direct {e["split"]["direct"]["interior"]["rel_rmse"]:.4f} indirect {e["split"]["indirect"]["interior"]["rel_rmse"]:.4f}')
PY
}
