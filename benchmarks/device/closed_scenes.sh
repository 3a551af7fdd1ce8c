#!/usr/bin/env bash
# Issue 26, session 13 (docs/lpv.md "Closed scenes"): lpv.coarse_iterations=auto on the device.
# 1. The original Cornell box from view=front (480x270, 4096-path full reference, reference.split=on): the defaults
#    (auto: closed, 48 steps), the open count (16) and band 2 (lpv.sh_order=2) -> $OUT/cb.txt.
# 2. Frames at 1080p (common.sh: medians of 100 frames after 20), two repetitions: the Cornell box and the gallery
#    with auto and with 16 steps, the atrium, restaurant and dragon (open: unchanged) -> $OUT/frames.md.
# 3. Band 2's propagation cost at 1080p (30 frames): 64 steps with and without energy conservation, 16 steps, and
#    band 1 at 64 steps -> $OUT/band2.md.
# Run from the repo root: BENCH=./build/rtgi-bench OUT=/tmp/out SCENES=../shared/scenes benchmarks/device/closed_scenes.sh
set -uo pipefail
source "$(dirname "$0")/common.sh"
C="$SCENES/cornell-box/cornell-box.gltf"
OPEN=(--set lpv.coarse_iterations=16)
mkdir -p "$OUT/b2"
cornell_front defaults
cornell_front open "${OPEN[@]}"
cornell_front band2 --set lpv.sh_order=2
for rep in 1 2; do
  one "$BENCH" "$OUT/f$rep" cornell-auto --scene "$C" --set view=front
  one "$BENCH" "$OUT/f$rep" cornell-open --scene "$C" --set view=front "${OPEN[@]}"
  one "$BENCH" "$OUT/f$rep" gallery-auto --scene builtin:gallery --set view=door
  one "$BENCH" "$OUT/f$rep" gallery-open --scene builtin:gallery --set view=door "${OPEN[@]}"
  one "$BENCH" "$OUT/f$rep" atrium --scene builtin:atrium
  one "$BENCH" "$OUT/f$rep" restaurant --scene builtin:restaurant
  one "$BENCH" "$OUT/f$rep" dragon "${DRAGON[@]}"
done
python3 - "$OUT" >"$OUT/frames.md" <<'PY'
import json, pathlib, sys
for p in sorted(pathlib.Path(sys.argv[1]).glob("f*/*/results.json")):
    d = json.loads(p.read_text()); ps = {q["name"]: q["gpu_ms"]["median"] for q in d["passes"]}
    lpv = sum(v for k, v in ps.items() if k.startswith("lpv.") and "/" not in k)
    print(f'{str(p.parent.relative_to(sys.argv[1])):24s} frame {d["total_ms"]:.3f} lpv {lpv:.3f} '
          f'propagate {ps.get("lpv.propagate", -1):.3f} coarse {d["config"]["lpv.coarse_iterations"]}')
PY
for v in "band2-64" "band2-64-noec lpv.energy_conserving=off" "band2-16 lpv.coarse_iterations=16" "band1-64 lpv.sh_order=1"; do
  set -- $v; n=$1; shift; extra=(); for kv in "$@"; do extra+=(--set "$kv"); done
  "$BENCH" --scene "$C" --set view=front --set lpv.sh_order=2 --set lpv.coarse_iterations=64 "${extra[@]}" \
    --res 1920x1080 --frames 30 --warmup 10 --no-images --out "$OUT/b2/$n" >"$OUT/b2-$n.log" 2>&1 || echo "FAILED $n"
  python3 - "$OUT/b2/$n/results.json" "$n" >>"$OUT/band2.md" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); ps = {q["name"]: q["gpu_ms"]["median"] for q in d["passes"]}
print(f'{sys.argv[2]:16s} frame {d["total_ms"]:.3f} propagate {ps.get("lpv.propagate", -1):.3f}')
PY
done
cat "$OUT/cb.txt" "$OUT/frames.md" "$OUT/band2.md"
