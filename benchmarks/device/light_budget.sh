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
  # Same generator as benchmarks/device/lights.sh: a 0.2 m tile and N point
  # lights under the gallery's ceiling on a k x k grid, total intensity 48.
  python3 - "$n" "$GEN/points$n.gltf" <<'PY'
import base64, json, math, struct, sys
n, path = int(sys.argv[1]), sys.argv[2]
pos = [(3.5, 0.001, 2.5), (3.7, 0.001, 2.5), (3.7, 0.001, 2.7), (3.5, 0.001, 2.7)]
blob = b"".join(struct.pack("<3f", *p) for p in pos) + b"".join(struct.pack("<3f", 0, 1, 0) for _ in pos)
blob += struct.pack("<6H", 0, 2, 1, 0, 3, 2)
k = math.ceil(math.sqrt(n))
lights, nodes = [], [{"mesh": 0}]
for i in range(n):
    x = -3.0 + 6.0 * ((i % k) + 0.5) / k
    z = -2.5 + 4.0 * ((i // k) + 0.5) / k
    lights.append({"type": "point", "intensity": 12.0 / n * 4.0, "color": [1.0, 0.9, 0.8]})
    nodes.append({"translation": [x, 3.2, z], "extensions": {"KHR_lights_punctual": {"light": i}}})
doc = {
    "asset": {"version": "2.0"}, "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": lights}},
    "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}], "nodes": nodes,
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
    "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 96, "byteLength": 12}],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [3.5, 0.001, 2.5], "max": [3.7, 0.001, 2.7]},
        {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
}
json.dump(doc, open(path, "w"))
PY
  for budget in 48 0; do
    "$BENCH" --scene builtin:gallery --scene "$GEN/points$n.gltf" --set light.budget=$budget "${COMMON[@]}" \
        --out "$OUT/light_budget/points$n-budget$budget"
  done
done
# Without the extra lights (the gallery's own three), for the base cost.
"$BENCH" --scene builtin:gallery "${COMMON[@]}" --out "$OUT/light_budget/gallery"

# Error against the path tracer (same run, both budgets; the reference is cached).
for budget in 48 0; do
  "$BENCH" --scene builtin:gallery --scene "$GEN/points16.gltf" --set light.budget=$budget --res 1920x1080 \
      --frames 1 --warmup 20 --no-images --reference --out "$OUT/light_budget/points16-budget$budget-error"
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
          f'error {json.dumps(r.get("error", {}).get("rmse", r.get("error", "-")))[:60]}')
PY
