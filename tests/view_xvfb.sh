#!/usr/bin/env bash
# rtgi-view under Xvfb (Mesa): renders builtin:cornell for 5 frames, writes a
# screenshot, which must not be blank and must match rtgi-bench's final.png of
# the same configuration (same scene camera, resolution and frame count).
# usage: view_xvfb.sh RTGI_VIEW RTGI_BENCH WORKDIR   (exit 77 = skipped: no xvfb-run)
set -euo pipefail
view=$1 bench=$2 work=$3
command -v xvfb-run > /dev/null || { echo "view_xvfb.sh: xvfb-run not installed, skipping"; exit 77; }
rm -rf "$work" && mkdir -p "$work"
args=(--scene builtin:cornell --res 160x120)

xvfb-run -a -s "-screen 0 640x480x24" "$view" "${args[@]}" --frames 5 --screenshot "$work/view.png"
# rtgi-bench renders warm-up + measured frames: 0 + 5 gives the same frame sequence.
"$bench" "${args[@]}" --frames 5 --warmup 0 --out "$work/bench" > /dev/null

# Without a display rtgi-view must fail with one clear sentence, not crash.
set +e
msg=$(env -u DISPLAY -u WAYLAND_DISPLAY "$view" "${args[@]}" --frames 1 2>&1 >/dev/null)
rc=$?
set -e
echo "no display: rc=$rc: $msg"
[ "$rc" -ne 0 ] && [ "$rc" -lt 128 ] || { echo "FAIL: rtgi-view without a display must exit non-zero without a signal"; exit 1; }
grep -q "cannot open a window" <<< "$msg" || { echo "FAIL: no clear message without a display"; exit 1; }

/usr/bin/python3 - "$work/view.png" "$work/bench/final.png" <<'PY'
import sys
import matplotlib.image as mpimg
import numpy as np
view, bench = (mpimg.imread(p)[..., :3].astype(np.float64) for p in sys.argv[1:3])
print("view", view.shape, "bench", bench.shape)
assert view.shape == bench.shape == (120, 160, 3), "screenshot size differs from --res"
# Not blank: the lit Cornell box spans a range of values, not a constant image.
assert view.std() > 0.02 and view.max() > 0.2, "screenshot is blank (std %.4f, max %.4f)" % (view.std(), view.max())
d = np.abs(view - bench)
print("mean |diff| %.5f, max |diff| %.5f, pixels off by > 2/255: %.4f %%" % (d.mean(), d.max(), 100 * (d > 2 / 255).mean()))
# Same renderer, camera, size and frames on the same llvmpipe: the images should agree to
# rounding. Tolerances: the GLX (Xvfb) and EGL (surfaceless) contexts may order float work
# differently, so allow a mean of 1/255 and at most 1 % of values off by more than 2/255.
assert d.mean() <= 1 / 255, "mean difference too large"
assert (d > 2 / 255).mean() <= 0.01, "too many differing pixels"
print("view_xvfb: OK")
PY
