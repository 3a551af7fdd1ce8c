#!/usr/bin/env bash
# Lights of issue 13 (docs/lights.md): cost per light type at 1080p —
# shadow.local (spot perspective map, point / area cube), lpv.rsm and
# lpv.inject for their RSMs, direct — on the original Cornell box (one
# emissive panel -> one area light) and builtin:gallery (two spot lights, one
# point light); the frame with 1, 4 and 16 point lights (builtin:gallery with
# its own lights scaled to zero, plus N point lights from a generated glTF);
# and the path tracer with and without emitter sampling on the Cornell box.
# Per-pass times land in results.json "passes"; rays/s in "stats".
# Run from the repo root with BENCH, OUT and SCENES set.
set -euo pipefail
BENCH=${BENCH:-./build/rtgi-bench}
OUT=${OUT:-out}
SCENES=${SCENES:-../shared/scenes}
CORNELL="$SCENES/cornell-box/cornell-box.gltf"
COMMON=(--res 1920x1080 --frames 100 --warmup 20 --no-images)
mkdir -p "$OUT/lights"

run() {
  local name=$1; shift
  "$BENCH" "$@" "${COMMON[@]}" --out "$OUT/lights/$name"
}

# Cost per light type, defaults (lpv=auto: on), and the shadow/RSM sizes swept.
for size in 256 512 1024; do
  run "cornell-local$size" --scene "$CORNELL" --set shadow.local_size=$size
  run "gallery-local$size" --scene builtin:gallery --set shadow.local_size=$size
done
run "cornell-lpv-off" --scene "$CORNELL" --set lpv=off
run "gallery-lpv-off" --scene builtin:gallery --set lpv=off
run "gallery-unshadowed" --scene builtin:gallery --set passes.off=shadow.local

# N point lights: a generated glTF (a 0.2 m tile in a corner of the gallery
# and N KHR_lights_punctual point lights under its ceiling) merged into the
# gallery.
GEN="$OUT/lights/generated"
mkdir -p "$GEN"
for n in 1 4 16; do
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
  # The gallery's own three lights stay (they are part of every variant).
  run "points$n" --scene builtin:gallery --scene "$GEN/points$n.gltf"
  run "points$n-lpv-off" --scene builtin:gallery --scene "$GEN/points$n.gltf" --set lpv=off
done

# Path tracer on the area-lit box: 64 paths with and without emitter sampling
# against 1024 (time and error; --reference compares the run's image).
"$BENCH" --scene "$CORNELL" --res 1920x1080 --frames 1 --warmup 0 --no-images --set reference=full \
    --set reference.spp=64 --set reference.cache=off --out "$OUT/lights/cornell-ref64-nee"
"$BENCH" --scene "$CORNELL" --res 1920x1080 --frames 1 --warmup 0 --no-images --set reference=full \
    --set reference.spp=64 --set reference.light_sampling=off --set reference.cache=off \
    --out "$OUT/lights/cornell-ref64-bsdf"
