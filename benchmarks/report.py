#!/usr/bin/python3
"""Turns sweep results (DIR/results.jsonl written by `rtgi-bench --sweep`) into
PNG plots and a markdown report: error-vs-time Pareto fronts per scene and
technique family, time-vs-work log-log scaling per pass, and the seed
comparison tables (seed 003 table 6.3 layout, seed 000 section 6.4 per-pass
timings side by side with ours). Format and reading: docs/benchmarks-howto.md.

usage: report.py DIR [DIR ...] [--out OUTDIR] [--title TEXT]
A DIR may also be a path run (`rtgi-bench --path P --reference --out DIR`:
results.json and temporal.csv) or hold path runs one level down: their error
and flicker per frame, and Pareto plots of mean error and mean flicker against
frame time (docs/temporal.md, "Plots").
Needs only Python 3, numpy and matplotlib (Debian python3-matplotlib,
python3-numpy). Run it with any python3: when that interpreter lacks
matplotlib (a virtualenv, a conda python), the script re-executes itself under
the system interpreter /usr/bin/python3.
"""
import argparse
import datetime
import json
import math
import os
import re
import sys
from collections import OrderedDict, defaultdict

SYSTEM_PYTHON = "/usr/bin/python3"
try:
    import matplotlib
    import numpy as np
except ImportError as missing:
    # Another interpreter (venv, conda, a self-built python) without the Debian
    # packages: run under the system one, once (the variable stops a loop).
    if os.environ.get("RTGI_REPORT_REEXEC") != "1" and os.path.exists(SYSTEM_PYTHON) and \
            os.path.realpath(sys.executable) != os.path.realpath(SYSTEM_PYTHON):
        os.environ["RTGI_REPORT_REEXEC"] = "1"
        os.execv(SYSTEM_PYTHON, [SYSTEM_PYTHON, os.path.abspath(__file__)] + sys.argv[1:])
    sys.exit("report.py: %s under %s; install Debian python3-matplotlib python3-numpy (apt-get install "
             "python3-matplotlib python3-numpy) or run it with %s" % (missing, sys.executable, SYSTEM_PYTHON))

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402

# Seed 000, section 6.4 (GTX 1050, 1920x1080, Sponza), as SPEC 8.4 quotes it:
# (label, ms, regexes of our pass names that do the same work).
SEED000 = [
    ("LPV", "RSM", 0.30, [r"^lpv\.rsm$"]),
    ("LPV", "light injection", 0.05, [r"^lpv\.inject$", r"^lpv\.inject[._-]?(light|rsm|flux)"]),
    ("LPV", "GV injection (G-buffer)", 0.50, [r"^lpv\.(gv|geometry)[._-]?.*(gbuffer|camera)"]),
    ("LPV", "GV injection (RSM)", 0.05, [r"^lpv\.(gv|geometry)[._-]?.*rsm"]),
    ("LPV", "propagation, 1 iteration", 0.23, [r"^lpv\.propagat"]),  # ours divided by lpv.iterations
    ("LPV", "combine", 0.07, [r"^lpv\.(combine|accumulate)"]),
    ("LPV", "temporal", 0.03, [r"^lpv\.temporal"]),
    ("LPV", "apply (with specular)", 1.78, [r"^lpv\.apply"]),
    ("LPV", "total (8 it., specular, occlusion+bounce)", 4.83, [r"^lpv\."]),
    ("AO", "SSAO 8 samples", 0.86, [r"^ao\.(ssao|vo|hbao|gtao|vbao|rtao)[^.]*$", r"^ao\.(trace|compute|main)"]),
    ("AO", "blur (total)", 1.24, [r"^ao\.blur"]),
    ("AO", "temporal", 0.23, [r"^ao\.temporal"]),
    ("AO", "near-field blend", 0.16, [r"^ao\.near"]),
    ("AO", "total", 2.66, [r"^ao\."]),
    ("SSR", "march", 0.34, [r"^ssr\.(march|trace|linear|dda|hiz)"]),
    ("SSR", "resolve", 0.19, [r"^ssr\.resolve"]),
    ("SSR", "blur (total)", 0.36, [r"^ssr\.blur"]),
    ("SSR", "temporal", 0.15, [r"^ssr\.temporal"]),
    ("SSR", "shading", 0.47, [r"^ssr\.(shade|shading|apply|compose)"]),
    ("SSR", "total", 1.51, [r"^ssr\."]),
]

# Work measures of the scaling plots: axis key -> (label, value from the string).
def _grid_cells(v):
    parts = [int(p) for p in v.split("x")]
    return float(parts[0] ** 3 if len(parts) == 1 else parts[0] * parts[1] * parts[2])


def _pixels(v):
    w, h = v.split("x")
    return float(int(w) * int(h))


WORK = OrderedDict([
    ("lpv.grid", ("grid cells", _grid_cells)),
    ("lpv.iterations", ("propagation iterations", float)),
    ("lpv.rsm", ("RSM texels", lambda v: float(int(v) ** 2))),
    ("ao.samples", ("AO samples per pixel", float)),
    ("ssr.steps", ("SSR steps", float)),
    ("resolution", ("pixels", _pixels)),
])

FAMILIES = ("lpv", "ao", "ssr")


def path_run_dirs(d):
    """Path runs in d: d itself when it holds temporal.csv, else its subdirectories that do (sorted)."""
    if os.path.exists(os.path.join(d, "temporal.csv")):
        return [d]
    if not os.path.isdir(d):
        return []
    return sorted(os.path.join(d, e) for e in os.listdir(d) if os.path.exists(os.path.join(d, e, "temporal.csv")))


def load(dirs):
    """Last successful line per configuration id, in first-seen order; failed lines listed apart."""
    results, failed, unreadable = OrderedDict(), OrderedDict(), 0
    for d in dirs:
        path = os.path.join(d, "results.jsonl")
        if not os.path.exists(path) and path_run_dirs(d):
            continue  # path runs only (load_path_runs)
        if not os.path.exists(path):
            sys.exit("report.py: %s does not exist (run rtgi-bench --sweep FILE --out %s first)" % (path, d))
        with open(path) as f:
            for line in f:
                if not line.strip():
                    continue
                try:
                    r = json.loads(line)
                    cid = r["sweep"]["id"]
                except (ValueError, KeyError, TypeError):
                    unreadable += 1
                    continue
                if "failed" in r:
                    failed[cid] = r
                else:
                    results[cid] = r
                    failed.pop(cid, None)
    return list(results.values()), list(failed.values()), unreadable


def cfg(r, key, default=None):
    """A configuration value as text, whether the line stores it typed (16, 0.5) or as a string ("16")."""
    v = r.get("config", {}).get(key, default)
    if v is None:
        return None
    if isinstance(v, bool):
        return "on" if v else "off"
    if isinstance(v, float) and v.is_integer():
        return str(int(v))
    return str(v)


def axis_text(v):
    return cfg({"config": {"v": v}}, "v")


def pass_ms(r):
    return {p["name"]: p["gpu_ms"]["median"] for p in r.get("passes", [])}


def family_ms(r, fam):
    return sum(ms for n, ms in pass_ms(r).items() if n.startswith(fam + "."))


def frame_ms(r):
    """Frame time without the reference passes (they are the ground truth, not the technique)."""
    refs = sum(ms for n, ms in pass_ms(r).items() if n.startswith("ref."))
    return r.get("total_ms", 0.0) - refs


def flatten_numbers(obj, prefix=""):
    out = OrderedDict()
    if isinstance(obj, dict):
        for k, v in obj.items():
            out.update(flatten_numbers(v, prefix + k + "."))
    elif isinstance(obj, (int, float)) and not isinstance(obj, bool) and math.isfinite(obj):
        out[prefix[:-1]] = float(obj)
    return out


def error_value(r):
    """(metric name, value): RMSE when present (SPEC 7.2), else the first numeric metric."""
    nums = flatten_numbers(r.get("error", {}))
    if not nums:
        return None, None
    for pick in (lambda k: k == "rmse", lambda k: k.endswith("rmse") and "rel" not in k, lambda k: "rmse" in k):
        for k, v in nums.items():
            if pick(k):
                return k, v
    k = next(iter(nums))
    return k, nums[k]


def error_text(r):
    """The configurations table's error cell: the RMSE corrected for the reference's noise with its 95 %
    interval when the run has them (issue 21), else the error_value metric."""
    e = r.get("error", {})
    if isinstance(e.get("rmse_debiased"), (int, float)) and isinstance(e.get("rmse_ci95"), list):
        lo, hi = e["rmse_ci95"]
        text = "rmse %.4g ± %.2g (debiased; 95 %% [%.4g, %.4g])" % (e["rmse_debiased"], (hi - lo) / 2, lo, hi)
        ratio = e.get("reference", {}).get("noise_ratio")
        if isinstance(ratio, (int, float)):
            text += ", ref. noise %.2f×" % ratio
        return text
    metric, err = error_value(r)
    return "%s %.4g" % (metric, err) if err is not None else ""


def technique(r):
    """(family, variant label) of a configuration; family None for a frame without LPV/AO/SSR passes."""
    names = pass_ms(r).keys()
    active = [f for f in FAMILIES if any(n.startswith(f + ".") for n in names)]
    if len(active) != 1:
        return ("frame" if active else None), "+".join(active) or "base"
    fam = active[0]
    if fam == "ao":
        return fam, cfg(r, "ao", "ao") + ("/half" if cfg(r, "ao.resolution") == "half" else "")
    if fam == "ssr":
        return fam, cfg(r, "ssr", "ssr")
    return fam, "lpv " + cfg(r, "lpv.path", "compute") + " " + cfg(r, "lpv.format", "")


# Keys that name the variant (colour) rather than a swept value (point label).
VARIANT_KEYS = {"ao", "ao.resolution", "ssr", "lpv.path", "lpv.format", "view", "lpv", "reference"}


def swept_label(r, varying):
    """The swept values of a configuration that are not its variant and differ between the plotted points:
    the point's label in the Pareto plot ("16" for ao.samples=16)."""
    axes = {k: v for k, v in r["sweep"].get("axes", {}).items() if k not in VARIANT_KEYS and k in varying}
    if not axes:
        return ""
    if len(axes) == 1:
        return axis_text(next(iter(axes.values())))
    return ",".join("%s=%s" % (k.split(".")[-1], axis_text(v)) for k, v in sorted(axes.items()))


def spans_decades(values):
    """Whether positive data span more than a decade: such an axis is drawn log-scaled."""
    vals = [v for v in values if v > 0]
    return len(vals) >= 2 and max(vals) / min(vals) > 10.0


def plain_log_ticks(axis):
    """Log axis ticks at 1, 2, 5 × 10^k printed as plain numbers ("0.02", "5", "200"), not "2×10⁻²"."""
    axis.set_major_locator(ticker.LogLocator(base=10.0, subs=(1.0, 2.0, 5.0), numticks=15))
    axis.set_major_formatter(ticker.FuncFormatter(lambda v, _: "%g" % v))
    axis.set_minor_formatter(ticker.NullFormatter())


def pareto_front(points):
    """Points not dominated in (time, error), sorted by time."""
    front, best = [], float("inf")
    for t, e in sorted(points):
        if e < best:
            front.append((t, e))
            best = e
    return front


def slug(s):
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", s).strip("_")


def plot_pareto(results, outdir):
    """One figure per scene: a panel per technique family, points coloured by variant, the front as a line."""
    made = []
    by_scene = defaultdict(list)
    values = defaultdict(lambda: defaultdict(set))  # scene -> axis -> values
    for r in results:
        for k, v in r["sweep"].get("axes", {}).items():
            values[r["sweep"]["scene_label"]][k].add(axis_text(v))
    for r in results:
        metric, err = error_value(r)
        fam, variant = technique(r)
        if err is None or fam is None:
            continue
        t = frame_ms(r) if fam == "frame" else family_ms(r, fam)
        scene = r["sweep"]["scene_label"]
        varying = {k for k, vs in values[scene].items() if len(vs) > 1}
        by_scene[scene].append((fam, variant, t, err, metric, swept_label(r, varying)))
    for scene, pts in sorted(by_scene.items()):
        fams = sorted({p[0] for p in pts})
        fig, axes = plt.subplots(1, len(fams), figsize=(5.2 * len(fams), 4.2), squeeze=False)
        for ax, fam in zip(axes[0], fams):
            sel = [p for p in pts if p[0] == fam]
            for i, v in enumerate(sorted({p[1] for p in sel})):
                xs = [p[2] for p in sel if p[1] == v]
                ys = [p[3] for p in sel if p[1] == v]
                ax.scatter(xs, ys, s=18, label=v, color=plt.cm.tab10(i % 10))
            # Each point carries the swept value (samples, grid, steps...) it was measured at.
            for p in sel:
                if p[5]:
                    ax.annotate(p[5], (p[2], p[3]), textcoords="offset points", xytext=(3, 3), fontsize=6, alpha=0.8)
            front = pareto_front([(p[2], p[3]) for p in sel])
            ax.plot([f[0] for f in front], [f[1] for f in front], "k-", lw=1, label="Pareto front")
            # Times and errors of one family often span decades (16 x the samples,
            # 8^3..256^3 grids): a linear axis crowds the cheap end near 0.
            if spans_decades([p[2] for p in sel]):
                ax.set_xscale("log")
                plain_log_ticks(ax.xaxis)
            if spans_decades([p[3] for p in sel]):
                ax.set_yscale("log")
                plain_log_ticks(ax.yaxis)
            ax.set_xlabel("GPU time of the %s passes [ms]" % fam if fam != "frame" else "frame time [ms]")
            ax.set_ylabel(sel[0][4])
            ax.set_title("%s: %s" % (scene, fam))
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
        fig.tight_layout()
        name = "pareto_%s.png" % slug(scene)
        fig.savefig(os.path.join(outdir, name), dpi=90)
        plt.close(fig)
        made.append((scene, name))
    return made


def plot_scaling(results, outdir):
    """Per sweep and work axis: median pass time vs work, log-log, geometric mean over scenes/views/other axes."""
    made = []
    by_sweep = defaultdict(list)
    for r in results:
        by_sweep[r["sweep"].get("name", "sweep")].append(r)
    for sweep, rs in sorted(by_sweep.items()):
        varying = defaultdict(set)
        for r in rs:
            for k, v in r["sweep"].get("axes", {}).items():
                varying[k].add(axis_text(v))
            varying["resolution"].add(r["resolution"])
        for key, (label, measure) in WORK.items():
            if len(varying.get(key, ())) < 2:
                continue
            series = defaultdict(lambda: defaultdict(list))  # pass -> work -> [ms]
            for r in rs:
                raw = r["resolution"] if key == "resolution" else r["sweep"].get("axes", {}).get(key)
                if raw is None:
                    continue
                raw = axis_text(raw)
                try:
                    w = measure(raw)
                except ValueError:
                    continue
                for n, ms in pass_ms(r).items():
                    if ms > 0 and not n.startswith("ref."):
                        series[n][w].append(ms)
            if not series:
                continue
            fig, ax = plt.subplots(figsize=(6.4, 4.6))
            slopes = {}
            for i, (n, pts) in enumerate(sorted(series.items())):
                ws = sorted(pts)
                if len(ws) < 2:
                    continue
                ms = [math.exp(np.mean(np.log(pts[w]))) for w in ws]
                slope = np.polyfit(np.log(ws), np.log(ms), 1)[0]
                slopes[n] = slope
                ax.loglog(ws, ms, "o-", ms=3, lw=1, color=plt.cm.tab20(i % 20), label="%s (slope %.2f)" % (n, slope))
            if not slopes:
                plt.close(fig)
                continue
            plain_log_ticks(ax.xaxis)
            plain_log_ticks(ax.yaxis)
            ax.set_xlabel(label)
            ax.set_ylabel("median GPU time [ms]")
            ax.set_title("%s: time vs %s" % (sweep, label))
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=6, ncol=2)
            fig.tight_layout()
            name = "scaling_%s_%s.png" % (slug(sweep), slug(key))
            fig.savefig(os.path.join(outdir, name), dpi=90)
            plt.close(fig)
            made.append((sweep, key, name, slopes))
    return made


def seed003_tables(results):
    """Seed 003 table 6.3 layout per scene: AO variant x 8/16/24 samples, RMSE and ms (mean over views)."""
    cells = defaultdict(lambda: defaultdict(list))  # (scene, res) -> (variant, samples) -> [(err, ms)]
    for r in results:
        fam, variant = technique(r)
        if fam != "ao":
            continue
        s = cfg(r, "ao.samples")
        if s not in ("8", "16", "24"):
            continue
        _, err = error_value(r)
        cells[(r["sweep"]["scene_label"], r["resolution"])][(variant, s)].append((err, family_ms(r, "ao")))
    out = []
    for (scene, res), c in sorted(cells.items()):
        variants = sorted({v for v, _ in c})
        lines = ["**%s, %s** (RMSE against ray-traced AO with the same radius; ms = all ao.* passes, median)" % (scene, res), "",
                 "| variant | 8: RMSE | 8: ms | 16: RMSE | 16: ms | 24: RMSE | 24: ms |",
                 "|---|---:|---:|---:|---:|---:|---:|"]
        for v in variants:
            row = [v]
            for s in ("8", "16", "24"):
                vals = c.get((v, s), [])
                errs = [e for e, _ in vals if e is not None]
                row.append("%.2f %%" % (100 * np.mean(errs)) if errs else "—")
                row.append("%.3f" % np.mean([m for _, m in vals]) if vals else "—")
            lines.append("| " + " | ".join(row) + " |")
        out.append("\n".join(lines))
    return out


def seed000_table(results):
    """Seed 000 6.4 per-pass timings beside ours (1920x1080; prefer the atrium and a full frame)."""
    cands = [r for r in results if r["resolution"] == "1920x1080"] or list(results)
    if not cands:
        return None

    def rank(r):
        names = pass_ms(r)
        fams = sum(any(n.startswith(f + ".") for n in names) for f in FAMILIES)
        return (fams, r["sweep"]["scene_label"] == "atrium", cfg(r, "lpv.iterations") == "8")

    best = {}
    for fam in FAMILIES:  # for each family the run that has it, with the most families on
        withfam = [r for r in cands if family_ms(r, fam) > 0]
        if withfam:
            best[fam] = max(withfam, key=rank)
    lines = ["| family | seed 000 step | seed ms (GTX 1050) | our passes | ours ms | our run |",
             "|---|---|---:|---|---:|---|"]
    for fam, label, seed_ms, patterns in SEED000:
        r = best.get(fam.lower())
        if r is None:
            lines.append("| %s | %s | %.2f | — | — | not measured |" % (fam, label, seed_ms))
            continue
        names = pass_ms(r)
        hit = []
        for pat in patterns:
            hit = [n for n in names if re.search(pat, n)]
            if hit:
                break
        ms = sum(names[n] for n in hit)
        if hit and label.startswith("propagation"):
            ms /= max(1, int(cfg(r, "lpv.iterations", "1")))
        ours = "%.3f" % ms if hit else "—"
        run = "%s %s %s" % (r["sweep"]["scene_label"], r["resolution"], r["sweep"].get("name", ""))
        lines.append("| %s | %s | %.2f | %s | %s | %s |" % (fam, label, seed_ms, ", ".join(hit) or "(no such pass)", ours, run))
    return "\n".join(lines)


def gi_suite_table(results):
    """Issue 22: per view, whether the LPV helps (gain = 1 - rmse / rmse without the LPV, on debiased RMSEs
    against the full reference), with LPV ms, the error's 95 % interval and the matching-bounce skill; the
    training views and the held-out views (the sweep's "held_out") separately, each with its mean and minimum."""
    rows = [r for r in results if isinstance(r.get("error", {}).get("gain", {}).get("lpv"), dict)]
    if not rows:
        return None
    out = []
    for split, title in ((False, "training views"), (True, "held-out views")):
        part = [r for r in rows if bool(r["sweep"].get("held_out")) == split]
        if not part:
            continue
        lines = ["**%s**" % title, "",
                 "| scene | view | res | LPV ms | RMSE (debiased, 95 %%) | RMSE lpv=off | gain | interior gain | "
                 "matching-bounce skill | direct rel. RMSE / bias | indirect rel. RMSE / bias | ref. noise / error | ref. spp |",
                 "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        gains = []
        for r in part:
            e = r["error"]
            g = e["gain"]["lpv"]
            lpv_ms = sum(ms for n, ms in pass_ms(r).items() if n.startswith("lpv."))
            lo, hi = e.get("rmse_ci95", [float("nan")] * 2)
            mb = e.get("matching_bounce", {}).get("skill")
            ref = e.get("reference", {})
            ratio = ref.get("noise_ratio")
            gains.append(g["gain"])
            sp = e.get("split", {})

            def part_error(k):
                # Issue 26 (reference.split=on): the direct and indirect parts' interior errors.
                x = sp.get(k, {}).get("interior", {})
                if not isinstance(x.get("rel_rmse"), (int, float)):
                    return "—"
                return "%.3f / %+.4f" % (x["rel_rmse"], x.get("bias", float("nan")))
            lines.append("| %s | %s | %s | %.3f | %.4f [%.4f, %.4f] | %.4f | %s%+.3f%s | %+.3f | %s | %s | %s | %s | %s |" % (
                r["sweep"]["scene_label"], r["sweep"].get("view") or "(own)", r["resolution"], lpv_ms,
                e.get("rmse_debiased", float("nan")), lo, hi, g["rmse_without"],
                "**" if g["gain"] <= 0 else "", g["gain"], "**" if g["gain"] <= 0 else "",
                g["interior"]["gain"], "%.3f" % mb if isinstance(mb, (int, float)) else "—",
                part_error("direct"), part_error("indirect"),
                "%.2f" % ratio if isinstance(ratio, (int, float)) else str(ratio), ref.get("spp", "—")))
        lines.append("")
        lines.append("%s: mean gain %.3f, minimum %.3f (%d views; **bold**: the LPV makes the image worse)." % (
            title, sum(gains) / len(gains), min(gains), len(gains)))
        out.append("\n".join(lines))
    return "\n\n".join(out)


def _number(text):
    try:
        v = float(text)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def load_path_runs(dirs):
    """One record per path run: its results.json and the per-frame columns of temporal.csv."""
    import csv
    runs = []
    for d in dirs:
        for run in path_run_dirs(d):
            try:
                with open(os.path.join(run, "results.json")) as f:
                    res = json.load(f)
            except (OSError, ValueError) as e:
                print("report.py: skipping %s: results.json unreadable (%s)" % (run, e), file=sys.stderr)
                continue
            if isinstance(res, list):  # one object per scene
                res = res[0] if res else {}
            with open(os.path.join(run, "temporal.csv")) as f:
                rows = list(csv.DictReader(f))
            cols = defaultdict(list)
            for row in rows:
                for k, v in row.items():
                    cols[k].append(_number(v))
            runs.append({"dir": run, "label": os.path.basename(os.path.normpath(run)), "res": res, "cols": cols,
                         "path": (res.get("path") or {}).get("name", "?"), "scene": res.get("scene", "?")})
    return runs


def _mean(values):
    v = [x for x in values if x is not None]
    return sum(v) / len(v) if v else None


def path_run_summary(run):
    """(mean frame ms, mean rmse, mean flicker) over the path's frames; None where not measured."""
    c = run["cols"]
    return _mean(c.get("frame_ms", [])), _mean(c.get("rmse", [])), _mean(c.get("flicker", []))


def plot_path_frames(runs, outdir):
    """Per path: error and flicker over the frames, one line per run (configuration)."""
    made = []
    by_path = defaultdict(list)
    for r in runs:
        by_path[(r["scene"], r["path"])].append(r)
    for (scene, path), sel in sorted(by_path.items()):
        fig, axes = plt.subplots(2, 1, figsize=(8.5, 6.0), sharex=True)
        plotted = False
        for i, r in enumerate(sel):
            frames = r["cols"].get("frame", [])
            for ax, key in zip(axes, ("rmse", "flicker")):
                pts = [(f, v) for f, v in zip(frames, r["cols"].get(key, [])) if f is not None and v is not None]
                if pts:
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], ".-", ms=3, lw=1,
                            color=plt.cm.tab10(i % 10), label=r["label"])
                    plotted = True
        if not plotted:
            plt.close(fig)
            continue
        events = ((sel[0]["res"].get("path") or {}).get("temporal") or {}).get("lag") or []
        for ax in axes:
            for e in events:
                if isinstance(e, dict) and e.get("event_frame") is not None:
                    ax.axvline(e["event_frame"], color="k", ls=":", lw=0.8)
            ax.grid(True, alpha=0.3)
        axes[0].set_ylabel("rmse against the reference")
        axes[1].set_ylabel("flicker (RMS of unexplained change)")
        axes[1].set_xlabel("path frame")
        axes[0].set_title("%s: %s" % (scene, path))
        axes[0].legend(fontsize=7)
        fig.tight_layout()
        name = "path_%s_%s.png" % (slug(scene), slug(path))
        fig.savefig(os.path.join(outdir, name), dpi=90)
        plt.close(fig)
        made.append(("%s: %s" % (scene, path), name))
    return made


def plot_path_pareto(runs, outdir):
    """Per path: mean error and mean flicker against mean frame time, each with its Pareto front."""
    made = []
    by_path = defaultdict(list)
    for r in runs:
        t, e, fl = path_run_summary(r)
        if t is not None and (e is not None or fl is not None):
            by_path[(r["scene"], r["path"])].append((r["label"], t, e, fl))
    for (scene, path), pts in sorted(by_path.items()):
        fig, axes = plt.subplots(1, 2, figsize=(10.4, 4.2), squeeze=False)
        for ax, idx, what in ((axes[0][0], 2, "mean rmse"), (axes[0][1], 3, "mean flicker")):
            sel = [(p[0], p[1], p[idx]) for p in pts if p[idx] is not None]
            for i, (label, t, v) in enumerate(sel):
                ax.scatter([t], [v], s=20, color=plt.cm.tab10(i % 10))
                ax.annotate(label, (t, v), textcoords="offset points", xytext=(3, 3), fontsize=6, alpha=0.8)
            front = pareto_front([(p[1], p[2]) for p in sel])
            if front:
                ax.plot([f[0] for f in front], [f[1] for f in front], "k-", lw=1, label="Pareto front")
                ax.legend(fontsize=7)
            ax.set_xlabel("mean frame time [ms]")
            ax.set_ylabel(what)
            ax.set_title("%s: %s, %s vs time" % (scene, path, what))
            ax.grid(True, alpha=0.3)
        fig.tight_layout()
        name = "path_pareto_%s_%s.png" % (slug(scene), slug(path))
        fig.savefig(os.path.join(outdir, name), dpi=90)
        plt.close(fig)
        made.append(("%s: %s" % (scene, path), name))
    return made


def path_runs_table(runs):
    """Markdown table: per run its path, mean frame time, error, flicker and the lags of its events."""
    lines = ["| run | scene | path | frames | frame ms | mean rmse | p95 rmse | mean flicker | disoccluded | lag (frames) |",
             "|---|---|---|---:|---:|---:|---:|---:|---:|---|"]
    fmt = lambda v, f="%.4g": "—" if v is None else f % v  # noqa: E731
    for r in runs:
        t, e, fl = path_run_summary(r)
        tj = (r["res"].get("path") or {}).get("temporal") or r["res"].get("temporal") or {}
        p95 = (tj.get("rmse") or {}).get("p95") if isinstance(tj.get("rmse"), dict) else None
        dis = (tj.get("disoccluded_fraction") or {}).get("mean") if isinstance(tj.get("disoccluded_fraction"), dict) else None
        lags = ", ".join("—" if not isinstance(x, dict) or x.get("frames") is None else str(x["frames"])
                         for x in (tj.get("lag") or []))
        lines.append("| %s | %s | %s | %d | %s | %s | %s | %s | %s | %s |" % (
            r["label"], r["scene"], r["path"], len(r["cols"].get("frame", [])), fmt(t, "%.3f"), fmt(e), fmt(p95),
            fmt(fl), fmt(dis, "%.3f"), lags or "—"))
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dirs", nargs="+", help="sweep output directories (each with results.jsonl)")
    ap.add_argument("--out", help="where report.md and the PNGs go (default: FIRST_DIR/report)")
    ap.add_argument("--title", default="rtgi benchmark report")
    a = ap.parse_args()
    outdir = a.out or os.path.join(a.dirs[0], "report")
    os.makedirs(outdir, exist_ok=True)
    results, failed, unreadable = load(a.dirs)
    runs = load_path_runs(a.dirs)

    md = ["# %s" % a.title, ""]
    if runs and not results:
        # Path runs only: the temporal report.
        r0 = runs[0]["res"]
        md += ["- device: %s (%s)" % (r0.get("device", "?"), r0.get("driver", "?")),
               "- path runs: %d" % len(runs),
               "- generated: %s by benchmarks/report.py from %s" % (
                   datetime.datetime.now().strftime("%Y-%m-%d %H:%M"), ", ".join(a.dirs)), ""]
    if runs:
        md += ["## Paths: error and flicker over the frames", "",
               "rmse and flicker (docs/temporal.md) of every referenced frame; dotted lines mark step events.", ""]
        frames_plots = plot_path_frames(runs, outdir)
        for title, name in frames_plots:
            md += ["### %s" % title, "", "![%s](%s)" % (title, name), ""]
        if not frames_plots:
            md += ["No path run has referenced frames (run rtgi-bench --path P --reference).", ""]
        md += ["## Paths: mean error and flicker against time", ""]
        pareto_paths = plot_path_pareto(runs, outdir)
        for title, name in pareto_paths:
            md += ["### %s" % title, "", "![%s](%s)" % (title, name), ""]
        md += [path_runs_table(runs), ""]
        if not results:
            with open(os.path.join(outdir, "report.md"), "w") as f:
                f.write("\n".join(md))
            print("report.py: wrote %s (%d plots)" % (os.path.join(outdir, "report.md"),
                                                     len(frames_plots) + len(pareto_paths)))
            return 0
    if results:
        r0 = results[0]
        md += ["- device: %s (%s)" % (r0.get("device", "?"), r0.get("driver", "?")),
               "- timer: %s%s" % (r0.get("timer", "?"), " (glFinish + CPU clock: no GPU timer queries)" if r0.get("timer") == "cpu" else ""),
               ]
    md += ["- sweeps: %s" % ", ".join(sorted({r["sweep"].get("name", "?") for r in results})) or "none",
           "- configurations: %d measured, %d failed%s" % (len(results), len(failed),
                                                            ", %d unreadable lines" % unreadable if unreadable else ""),
           "- generated: %s by benchmarks/report.py from %s" % (datetime.datetime.now().strftime("%Y-%m-%d %H:%M"), ", ".join(a.dirs)),
           ""]
    with_error = [r for r in results if error_value(r)[1] is not None]

    md += ["## Error vs time (Pareto fronts)", ""]
    pareto = plot_pareto(results, outdir)
    if pareto:
        md.append("Each point is one configuration: x = median GPU time of the technique's passes, y = its error "
                  "against the matching reference; the black line joins the configurations no other one beats in both.")
        md.append("")
        for scene, name in pareto:
            md += ["### %s" % scene, "", "![%s](%s)" % (scene, name), ""]
    elif any("retry" in r for r in results):
        md += ["No configuration has error values: the sweep asked for a reference, but the build that ran it has "
               "no reference passes (lines marked `retry`; resume in a build with them re-runs those lines).", ""]
    elif not any(cfg(r, "reference", "off") != "off" for r in results):
        md += ["No configuration has error values: the sweep asked for no reference. Add "
               "`\"reference\": \"ao\"` (or `indirect`, `full`) to the sweep file for error-vs-time plots "
               "(docs/benchmarks-howto.md).", ""]
    else:
        md += ["No configuration has error values although some asked for a reference (see the lines' `error`).", ""]

    md += ["## Time vs work (log-log)", ""]
    scaling = plot_scaling(results, outdir)
    if scaling:
        md.append("Median GPU time per pass against the work an axis sets (geometric mean over scenes, views and the "
                  "other axes); the slope of a log-log fit is 1 for linear scaling.")
        md.append("")
        for sweep, key, name, slopes in scaling:
            md += ["### %s: %s" % (sweep, key), "", "![%s %s](%s)" % (sweep, key, name), ""]
    else:
        md += ["No sweep varies a work axis (%s) over two or more values." % ", ".join(WORK), ""]

    gi = gi_suite_table(results)
    if gi:
        md += ["## GI suite: does the LPV help?", "", gi, ""]

    md += ["## Seed 003, table 6.3 layout", ""]
    t003 = seed003_tables(results)
    md += (t003 and ["\n\n".join(t003), "",
                     "Seed 003 measured RMSE of 2.3–5.7 % (VO), 2.4–5.7 % (HBAO) and 4.8–9.8 % (SSAO disk) at "
                     "8/16/24 samples (GTX 680 / HD 6970, 1920x1080); its ms are not comparable across GPUs.", ""]
           or ["No AO configuration with 8, 16 or 24 samples.", ""])

    md += ["## Seed 000, section 6.4: per-pass timings", ""]
    t000 = seed000_table(results)
    md += [t000 or "No results.", ""]

    md += ["## Configurations", "",
           "| id | sweep | configuration | frame ms | %s |" % ("error" if with_error else "—"), "|---|---|---|---:|---:|"]
    for r in results:
        md.append("| %s | %s | %s | %.3f | %s |" % (r["sweep"]["id"], r["sweep"].get("name", ""), r["sweep"].get("label", ""),
                                                  frame_ms(r), error_text(r)))
    if failed:
        md += ["", "### Failed", ""]
        for r in failed:
            md.append("- `%s` %s: %s" % (r["sweep"]["id"], r["sweep"].get("label", ""), r["failed"]))
    md.append("")
    with open(os.path.join(outdir, "report.md"), "w") as f:
        f.write("\n".join(md))
    print("report.py: wrote %s (%d plots)" % (os.path.join(outdir, "report.md"), len(pareto) + len(scaling)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
