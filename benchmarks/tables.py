#!/usr/bin/env python3
"""Markdown tables of per-pass GPU medians from a tree of results.json files
(the layout benchmarks/device/*.sh write: <family>/<config>/results.json).

    python3 benchmarks/tables.py DIR [--family lpv]
"""
import json
import os
import sys


def load(root):
    runs = []
    for dirpath, _, files in os.walk(root):
        if "results.json" in files:
            with open(os.path.join(dirpath, "results.json")) as f:
                r = json.load(f)
            r["_path"] = os.path.relpath(dirpath, root)
            runs.append(r)
    return sorted(runs, key=lambda r: r["_path"])


def table(runs):
    passes = []
    for r in runs:
        for p in r["passes"]:
            if p["name"] not in passes:
                passes.append(p["name"])
    head = "| run | timer | " + " | ".join(passes) + " | frame |"
    lines = [head, "|" + "---|" * (len(passes) + 3)]
    for r in runs:
        med = {p["name"]: p["gpu_ms"]["median"] for p in r["passes"]}
        cells = [f"{med[p]:.3f}" if p in med else "–" for p in passes]
        lines.append(f"| {r['_path']} | {r['timer']} | " + " | ".join(cells) + f" | {r['total_ms']:.3f} |")
    return "\n".join(lines)


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    runs = load(sys.argv[1])
    if "--family" in sys.argv:
        fam = sys.argv[sys.argv.index("--family") + 1]
        runs = [r for r in runs if r["_path"].split(os.sep)[0] == fam]
    if not runs:
        print("no results.json under " + sys.argv[1], file=sys.stderr)
        return 1
    r0 = runs[0]
    print(f"Device: {r0['device']} — driver {r0['driver']} — GL {r0['gl_version']}; medians in ms over "
          f"{r0['frames']} frames after {r0['warmup']} warm-up.\n")
    print(table(runs))
    return 0


if __name__ == "__main__":
    sys.exit(main())
