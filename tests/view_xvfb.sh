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

# The panel and the live reference (docs/viewer.md): --script actions go through
# the panel's own functions (applyPanelSetting + reconfigure, the layout state).
cat > "$work/script.txt" <<EOF
1 image ao
2 screenshot $work/ao_r05.png
3 set ao.radius 3
7 screenshot $work/ao_r3.png
8 reference on
8 compare split
8 split 0.5
20 screenshot $work/split.png
EOF
aoargs=(--scene builtin:box-on-plane --res 160x120 --set ao=gtao --set ao.resolution=full --set reference.spp=32)
xvfb-run -a -s "-screen 0 640x480x24" "$view" "${aoargs[@]}" --frames 21 --script "$work/script.txt" > /dev/null 2>&1
"$bench" "${aoargs[@]}" --set ao.radius=3 --set reference.cache=off --frames 1 --warmup 0 --reference --out "$work/ref" > /dev/null 2>&1

# --path (docs/viewer.md, "Paths"): played from frame 0, the viewer's frame k is rtgi-bench's path frame k
# (histories continued the same way); with the history reset every frame the temporal AO is not the same.
cat > "$work/path.txt" <<EOF
0 path play
4 screenshot $work/path4.png
5 image ao
5 screenshot $work/path5_ao.png
EOF
cat > "$work/path_reset.txt" <<EOF
0 path play
0 history reset
0 image ao
5 screenshot $work/path5_ao_reset.png
EOF
pargs=(--scene builtin:cornell --res 160x120 --path cornell-moving-box)
xvfb-run -a -s "-screen 0 640x480x24" "$view" "${pargs[@]}" --frames 6 --script "$work/path.txt" > /dev/null 2>&1
xvfb-run -a -s "-screen 0 640x480x24" "$view" "${pargs[@]}" --frames 6 --script "$work/path_reset.txt" > /dev/null 2>&1
"$bench" "${pargs[@]}" --frames 6 --warmup 0 --path-frames --out "$work/path" > /dev/null 2>&1

/usr/bin/python3 - "$work" <<'PY'
import sys
import matplotlib.image as mpimg
import numpy as np
w = sys.argv[1]
grey = lambda p: mpimg.imread(p)[..., 0].astype(np.float64)
r05, r3, split, ref = (grey("%s/%s" % (w, f)) for f in ("ao_r05.png", "ao_r3.png", "split.png", "ref/ref.ao.png"))
print("AO mean: radius 0.5 %.4f, radius 3 %.4f" % (r05.mean(), r3.mean()))
# A larger radius finds more occluders (the box and the floor around it): the panel's edit took effect.
assert r3.mean() < r05.mean() - 0.01, "ao.radius set through the panel did not change the AO"
L, R = slice(0, 78), slice(82, 160)  # the halves, without the split line at x = 80
tech_l = np.abs(split[:, L] - r3[:, L]).mean()
ref_r = np.abs(split[:, R] - ref[:, R]).mean()
ref_vs_tech = np.abs(ref[:, R] - r3[:, R]).mean()
print("split: left vs technique %.4f, right vs reference %.4f (reference vs technique there %.4f)"
      % (tech_l, ref_r, ref_vs_tech))
assert tech_l < 0.01, "left of the split is not the technique's AO"
# The progressive reference (4 samples a frame) and rtgi-bench's (16 a dispatch) draw the same
# samples; only the float summation order differs.
assert ref_r < 1.5 / 255, "right of the split is not the reference"
assert ref_vs_tech > 3 * ref_r, "the two sides would pass for each other: the check proves nothing"
print("view_xvfb: panel and split view OK")
PY

/usr/bin/python3 - "$work" <<'PY'
import sys
import matplotlib.image as mpimg
import numpy as np
w = sys.argv[1]
rgb = lambda p: mpimg.imread(p)[..., :3].astype(np.float64)
view, bench = rgb(w + "/path4.png"), rgb(w + "/path/frames/frame_0004.png")
ao, ao_reset = rgb(w + "/path5_ao.png"), rgb(w + "/path5_ao_reset.png")
d, r = np.abs(view - bench), np.abs(ao - ao_reset)
print("path frame 4: viewer vs rtgi-bench mean |diff| %.5f (off by > 2/255: %.4f %%); frame 5 AO, live vs reset "
      "history: max |diff| %.4f, off by > 2/255: %.2f %%" % (d.mean(), 100 * (d > 2 / 255).mean(), r.max(),
                                                           100 * (r > 2 / 255).mean()))
assert d.mean() <= 1 / 255 and (d > 2 / 255).mean() <= 0.01, "the viewer's path frame 4 is not rtgi-bench's"
# Without history the AO is one frame's noisy estimate: it differs from the filtered one by more than the
# tolerance that the viewer and rtgi-bench agree within (measured: 0.22 max, 8.9 % of values).
assert r.max() > 0.05 and (r > 2 / 255).mean() > 0.02, "resetting the history every frame changed nothing"
print("view_xvfb: path playback OK")
PY

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
