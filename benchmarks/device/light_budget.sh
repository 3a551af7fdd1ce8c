#!/usr/bin/env bash
# The per-frame light budget (docs/lights.md "Light budget"; issue 24
# deliverable 2, issue 28): builtin:gallery + 16 and + 64 point lights at
# 1080p, defaults (light.budget=48: every face drawn once during the warm-up,
# then reused from the cache; local RSMs at 128² for 16 lights, 64² for 64)
# against light.budget=0 (every face every frame, full-size RSMs: the frame
# before the budget), medians of 100 frames after 20 (results.json
# "total_ms", "passes": shadow.local, lpv.rsm, lpv.inject; "stats":
# shadow.local.layers / faces_cached, lpv.rsm.local_injected). Then the error
# effect of the budget against the path tracer (--reference: full image vs the
# cached path-traced reference; results.json "error"), 16 lights, both budgets.
# Target (issue 24): gallery + 16 point lights <= 6 ms (25.9 ms before, H100).
# Run from the repo root with BENCH and OUT set.
set -euo pipefail
BENCH=${BENCH:-./build/rtgi-bench}
OUT=${OUT:-out}
COMMON=(--res 1920x1080 --frames 100 --warmup 20 --no-images)
GEN="$OUT/light_budget/generated"
mkdir -p "$GEN"

for n in 16 64; do
  python3 benchmarks/device/point_lights.py "$n" "$GEN/points$n.gltf"  # the generator of lights.sh
  for budget in 48 0; do
    "$BENCH" --scene builtin:gallery --scene "$GEN/points$n.gltf" --set light.budget=$budget "${COMMON[@]}" \
        --out "$OUT/light_budget/points$n-budget$budget"
  done
done
# Without the extra lights (the gallery's own three), for the base cost.
"$BENCH" --scene builtin:gallery "${COMMON[@]}" --out "$OUT/light_budget/gallery"

# Error against the path tracer (same run, both budgets; the reference is cached).
for budget in 48 0; do
  "$BENCH" --scene builtin:gallery --scene "$GEN/points16.gltf" --set light.budget=$budget --res 480x270 \
      --frames 1 --warmup 20 --no-images --reference --set reference=full --out "$OUT/light_budget/points16-budget$budget-error"
done
# Under motion (the budget's worst case): benchmarks/paths/gallery.json "gallery-sphere-move" moves the sphere every
# frame, so every cached face is stale every frame and the budget redraws 48 faces a frame; the path tracer every
# 5th frame (results.json "temporal": rmse_debiased over the referenced frames).
for budget in 48 0; do
  "$BENCH" --scene builtin:gallery --scene "$GEN/points16.gltf" --set light.budget=$budget --res 480x270 \
      --path gallery-sphere-move --warmup 20 --no-images --reference --set reference=full --set reference.spp=256 \
      --reference-every 5 --out "$OUT/light_budget/points16-budget$budget-moving"
done
python3 - "$OUT/light_budget" <<'PY'
import json, os, sys
d = sys.argv[1]
for name in sorted(os.listdir(d)):
    p = os.path.join(d, name, "results.json")
    if not os.path.exists(p): continue
    r = json.load(open(p))
    ms = {x["name"]: x["gpu_ms"]["median"] for x in r.get("passes", [])}
    st = r.get("stats", {})
    print(f'{name:28s} frame {r.get("total_ms", 0):7.2f} ms  shadow.local {ms.get("shadow.local", 0):6.2f}  '
          f'lpv.rsm {ms.get("lpv.rsm", 0):6.2f}  lpv.inject {ms.get("lpv.inject", 0):6.2f}  '
          f'layers {st.get("shadow.local.layers", "-")}  cached {st.get("shadow.local.faces_cached", "-")}  '
          f'error {json.dumps(r.get("error", {}).get("rmse_debiased", r.get("error", "-")))[:60]}')
    t = r.get("temporal", {}).get("rmse_debiased")
    if t: print(f'{"":28s} moving: rmse_debiased mean {t["mean"]:.5f} max {t["max"]:.5f} over {t["frames"]} frames')
PY
