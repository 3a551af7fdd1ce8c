#!/usr/bin/env bash
# Issue 26, session 14 (docs/lights.md "Penumbrae from several origins"): emissive.split on the device.
# 1. The original Cornell box from view=front (480x270, 4096-path full reference, reference.split=on) with
#    emissive.split 1, auto (2), 3 and 4 -> $OUT/cb.txt (interior relative RMSE, its direct and indirect parts).
# 2. Frames at 1080p (common.sh: medians of 100 frames after 20), two repetitions, the Cornell box front with
#    split 1, 2, 3 and 4, and the per-pass cost of the passes the split multiplies (direct, shadows, RSM, injection)
#    -> $OUT/frames.md.
# Run from the repo root: BENCH=./build/rtgi-bench OUT=/tmp/out SCENES=../shared/scenes benchmarks/device/area_split.sh
set -uo pipefail
source "$(dirname "$0")/common.sh"
C="$SCENES/cornell-box/cornell-box.gltf"
cornell_front auto
cornell_front split1 --set emissive.split=1
cornell_front split3 --set emissive.split=3
cornell_front split4 --set emissive.split=4
for rep in 1 2; do
  for n in 1 2 3 4; do one "$BENCH" "$OUT/f$rep" "cornell-split$n" --scene "$C" --set view=front --set emissive.split=$n; done
done
python3 - "$OUT" >"$OUT/frames.md" <<'PY'
import json, pathlib, sys
for p in sorted(pathlib.Path(sys.argv[1]).glob("f*/*/results.json")):
    d = json.loads(p.read_text()); ps = {q["name"]: q["gpu_ms"]["median"] for q in d["passes"]}
    pick = {k: round(v, 3) for k, v in ps.items() if "/" not in k and any(s in k for s in ("direct", "shadow", "rsm", "inject"))}
    slow = {q["name"]: round(q["gpu_ms"]["max"], 2) for q in d["passes"] if q["gpu_ms"]["max"] > 2.0}
    print(f'{str(p.parent.relative_to(sys.argv[1])):24s} frame {d["total_ms"]:.3f} {pick} max>2ms {slow}')
PY
cat "$OUT/cb.txt" "$OUT/frames.md"
