#!/usr/bin/env python3
"""Per-pass table of the frame runs that benchmarks/device/frame.sh wrote:
frame_table.py DIR [BASE_DIR]. One block per run: the frame's median total
and each pass's median (ms), with the same pass of BASE_DIR beside it."""
import json
import pathlib
import sys


def load(directory):
    runs = {}
    for path in sorted(pathlib.Path(directory).glob("*/results.json")):
        doc = json.loads(path.read_text())
        passes = {p["name"]: p["gpu_ms"]["median"] for p in doc.get("passes", [])}
        runs[path.parent.name] = (doc.get("total_ms"), passes, doc.get("device", ""))
    return runs


def fmt(x):
    return "-" if x is None else f"{x:.3f}"


def main():
    runs = load(sys.argv[1])
    base = load(sys.argv[2]) if len(sys.argv) > 2 else {}
    for name, (total, passes, device) in runs.items():
        btotal, bpasses, _ = base.get(name, (None, {}, ""))
        print(f"\n## {name}  ({device})\n| pass | ms |" + (" base ms |" if base else ""))
        print("|---|---:|" + ("---:|" if base else ""))
        for p, ms in passes.items():
            print(f"| {p} | {fmt(ms)} |" + (f" {fmt(bpasses.get(p))} |" if base else ""))
        print(f"| **frame** | **{fmt(total)}** |" + (f" **{fmt(btotal)}** |" if base else ""))


if __name__ == "__main__":
    main()
