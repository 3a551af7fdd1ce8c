#!/usr/bin/env python3
"""Writes a glTF with N KHR_lights_punctual point lights under the ceiling of
builtin:gallery (and a 0.2 m floor tile so the file has a mesh), to be merged
into the gallery: point_lights.py N OUT.gltf"""
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
