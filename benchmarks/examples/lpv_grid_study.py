#!/usr/bin/python3
"""LPV grid study from Python (docs/python.md): sweep lpv.grid, plot the error of
the indirect light against the frame time, save the figure.

    PYTHONPATH=build/python python3 benchmarks/examples/lpv_grid_study.py          # small, llvmpipe-sized
    PYTHONPATH=build/python python3 benchmarks/examples/lpv_grid_study.py \\
        --scene builtin:atrium --view court --res 1920x1080 --grids 8 16 32 64 128 --frames 100 --warmup 20

Each configuration is timed without the reference and then compared with the
path-traced indirect light (the sweep's "reference": "indirect", as
benchmarks/sweeps/lpv-grid.json); the error is error.rmse_debiased (the
reference's own noise removed) with its 95 % interval as error bars. The
default run (cornell, 96x72, grids 8..32, 2 frames) takes a minute or two on
llvmpipe; its times are CPU-rasterizer times, not performance numbers.

Like benchmarks/report.py it re-executes itself under /usr/bin/python3 (Debian's
python3-numpy and python3-matplotlib) when this interpreter lacks them.
"""
import argparse
import os
import sys

SYSTEM_PYTHON = "/usr/bin/python3"


def _ensure_modules():
    try:
        import matplotlib  # noqa: F401
        import numpy  # noqa: F401
    except ImportError as e:
        if os.path.exists(SYSTEM_PYTHON) and os.path.realpath(sys.executable) != os.path.realpath(SYSTEM_PYTHON):
            os.execv(SYSTEM_PYTHON, [SYSTEM_PYTHON, os.path.abspath(__file__)] + sys.argv[1:])
        sys.exit("lpv_grid_study.py: %s in %s (apt-get install python3-matplotlib python3-numpy)" % (e, sys.executable))


def _find_rtgi():
    """rtgi from PYTHONPATH, an installed package, or this checkout's build/python."""
    try:
        import rtgi  # noqa: F401
    except ImportError:
        here = os.path.dirname(os.path.abspath(__file__))
        sys.path.insert(0, os.path.join(here, "..", "..", "build", "python"))
        import rtgi  # noqa: F401


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default="builtin:cornell")
    ap.add_argument("--view", default=None, help="named view of benchmarks/views/ (default: the scene's camera)")
    ap.add_argument("--res", default="96x72")
    ap.add_argument("--grids", type=int, nargs="+", default=[8, 16, 32])
    ap.add_argument("--frames", type=int, default=2)
    ap.add_argument("--warmup", type=int, default=1)
    ap.add_argument("--spp", type=int, default=64, help="reference samples per pixel (reference.spp)")
    ap.add_argument("--out", default="out/lpv_grid_study.png")
    args = ap.parse_args()

    _ensure_modules()
    _find_rtgi()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    import rtgi

    scene = {"scene": args.scene}
    if args.view:
        scene["views"] = [args.view]
    spec = {
        "name": "lpv-grid-study",
        "scenes": [scene],
        "resolutions": [args.res],
        "frames": args.frames,
        "warmup": args.warmup,
        "reference": "indirect",
        "base": {"lpv": "on", "ao": "off", "ssr": "off", "reference.spp": args.spp},
        "axes": [{"lpv.grid": args.grids}],
    }
    rows, devices = [], set()

    def progress(done, total, row):
        msg = row.get("failed") or "%.3f ms/frame, rmse %.4g" % (row["total_ms"], row["error"]["rmse_debiased"])
        print("[%d/%d] lpv.grid=%s: %s" % (done, total, row["sweep"]["axes"]["lpv.grid"], msg), file=sys.stderr)

    for row in rtgi.sweep(spec, progress=progress):
        if "failed" in row:
            continue
        devices.add(row["device"])
        lpv_ms = sum(p["gpu_ms"]["median"] for p in row["passes"] if p["name"].startswith("lpv."))
        e = row["error"]
        rows.append((row["config"]["lpv.grid"], row["total_ms"], lpv_ms, e["rmse_debiased"], *e["rmse_ci95"],
                     e["matching_bounce"]["rmse"] if "matching_bounce" in e else np.nan))
    if not rows:
        sys.exit("lpv_grid_study.py: every configuration failed")
    grid, total, lpv, rmse, lo, hi, mb = (np.array(c, dtype=float) for c in zip(*rows))

    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for a, x, label in ((ax[0], total, "frame time (median ms)"), (ax[1], lpv, "LPV passes (median ms)")):
        a.errorbar(x, rmse, yerr=[rmse - lo, hi - rmse], marker="o", capsize=3, label="vs full indirect")
        if np.isfinite(mb).any():
            a.plot(x, mb, "s--", label="vs matching bounce")
        for xi, yi, g in zip(x, rmse, grid):
            a.annotate("%d³" % g, (xi, yi), textcoords="offset points", xytext=(4, 4), fontsize=8)
        a.set_xlabel(label)
        a.set_ylabel("RMSE of the indirect light (debiased)")
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    device = ", ".join(sorted(devices))
    if "llvmpipe" in device:
        device += " (CPU rasterizer: the times are no performance numbers)"
    fig.suptitle("%s %s, lpv.grid sweep on %s" % (args.scene, args.res, device), fontsize=9)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    fig.savefig(args.out, dpi=120)
    print("lpv_grid_study.py: wrote %s (%d configurations)" % (args.out, len(rows)))
    for g, t, l_, r in zip(grid, total, lpv, rmse):
        print("  lpv.grid=%3d  frame %.3f ms  lpv %.3f ms  rmse %.5g" % (g, t, l_, r))


if __name__ == "__main__":
    main()
