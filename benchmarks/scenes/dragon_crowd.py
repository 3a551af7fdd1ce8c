#!/usr/bin/env python3
"""Writes a glTF that instances the Stanford dragon N times (default 50: 5 M
triangles) on a grid, referencing the shared dragon.bin by a relative path; the
data is never copied (issue 14, docs/visibility.md "Scale").

  python3 benchmarks/scenes/dragon_crowd.py SCENES_DIR OUT.gltf [N]
"""
import json
import math
import os
import sys


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: dragon_crowd.py SCENES_DIR OUT.gltf [N]")
    scenes, out = sys.argv[1], sys.argv[2]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 50
    src = os.path.join(scenes, "stanford-dragon", "dragon.gltf")
    with open(src) as f:
        g = json.load(f)
    # glTF URIs are relative to the file: point back at the shared buffer.
    binary = os.path.abspath(os.path.join(scenes, "stanford-dragon", g["buffers"][0]["uri"]))
    g["buffers"][0]["uri"] = os.path.relpath(binary, os.path.dirname(os.path.abspath(out)))
    side = math.ceil(math.sqrt(n))
    nodes = []
    for i in range(n):
        x, z = i % side, i // side
        # 3 x 2 units per dragon (about 2.7 x 1.2 in size), centred on the origin.
        nodes.append({"name": f"dragon_{i}", "mesh": 0,
                      "translation": [3.0 * (x - (side - 1) / 2), 0.0, 2.0 * (z - (side - 1) / 2)]})
    g["nodes"] = nodes
    g["scenes"] = [{"nodes": list(range(n))}]
    g["asset"]["generator"] = f"benchmarks/scenes/dragon_crowd.py ({n} instances)"
    with open(out, "w") as f:
        json.dump(g, f)


if __name__ == "__main__":
    main()
