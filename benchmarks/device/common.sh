# Shared by the frame scripts of benchmarks/device (sourced, not run): the defaults of BENCH, OUT and
# SCENES, the run arguments (RES, FRAMES, WARMUP; a script sets its own FRAMES default before sourcing),
# and the two loops every script had a copy of.
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
