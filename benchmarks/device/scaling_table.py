#!/usr/bin/env python3
"""The scaling table of benchmarks/device/scaling.sh: scaling_table.py DIR. Per scene and raster
path, the frame and the pass groups (ms, medians) at each resolution, and the triangle count."""
import json
import pathlib
import sys

GROUPS = [("visibility / G-buffer", ("visibility.", "gbuffer")), ("shadow", ("shadow",)), ("direct", ("direct",)),
          ("ao", ("ao.",)), ("ssr", ("ssr.",)), ("lpv.inject*", ("lpv.rsm", "lpv.inject", "lpv.pack")),
          ("lpv.propagate", ("lpv.propagate",)), ("lpv.apply", ("lpv.apply", "lpv.upsample")),
          ("post", ("post.",))]


def main():
    runs = {}
    for path in sorted(pathlib.Path(sys.argv[1]).glob("*/results.json")):
        doc = json.loads(path.read_text())
        scene, res, rpath = path.parent.name.rsplit("-", 2)
        runs.setdefault((scene, rpath), {})[res] = doc
    resolutions = ["1280x720", "1920x1080", "2560x1440", "3840x2160"]
    for (scene, rpath), by_res in sorted(runs.items()):
        cols = [r for r in resolutions if r in by_res]
        any_doc = by_res[cols[0]]
        print(f"\n### {scene}, raster.path={rpath} ({any_doc.get('triangles', '?')} triangles; {any_doc.get('device', '')})\n")
        print("| pass group (ms) | " + " | ".join(cols) + " |")
        print("|---|" + "---:|" * len(cols))
        for label, prefixes in GROUPS:
            vals = []
            for r in cols:
                ms = sum(p["gpu_ms"]["median"] for p in by_res[r].get("passes", [])
                         if p["name"].startswith(prefixes) and p["name"] != "lpv.visibility")
                vals.append(f"{ms:.3f}")
            print(f"| {label} | " + " | ".join(vals) + " |")
        print("| **frame** | " + " | ".join(f"**{by_res[r].get('total_ms', 0):.3f}**" for r in cols) + " |")


if __name__ == "__main__":
    main()
