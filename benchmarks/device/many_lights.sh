#!/usr/bin/env bash
# Issue 24 deliverable 2, "Many lights" (docs/lights.md "Injection cache", docs/lpv.md "Injection"):
# builtin:gallery + 16 and + 64 point lights (benchmarks/device/point_lights.py) at 1080p, medians of
# 60 frames after 20 warm-up frames (the light budget draws every face during the warm-up), with
# the local lights' injection cache on (default) and off (lpv.inject_cache=off: every face injected
# every frame, one batched dispatch per RSM array and cascade), each with profile.dispatches=on
# (per-dispatch scopes: lpv.inject/inject counts the injection dispatches). Prints the frame and
# lpv.inject medians and the dispatch counts. Target (issue 24): gallery + 16 point lights <= 6 ms
# (10.5 ms before this branch on an H200, lpv.inject 7.8 ms in 208 dispatches; + 64: 24.0 ms,
# lpv.inject 19.1 ms in 784 dispatches).
# BASE=path/to/another/rtgi-bench (e.g. main before this branch) runs the same cases with that
# binary (it does not know lpv.inject_cache: only its defaults) into $OUT/many_lights-base, same call.
# Run from the repo root with BENCH, OUT and SCENES set (SCENES is unused: the scenes are builtin
# and generated; it is accepted for symmetry with the other scripts).
FRAMES=${FRAMES:-60}
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
COMMON+=(--set profile.dispatches=on)
GEN="$OUT/many_lights/generated"
mkdir -p "$GEN"

for n in 16 64; do
  python3 benchmarks/device/point_lights.py "$n" "$GEN/points$n.gltf"
  for cache in on off; do
    one "$BENCH" "$OUT/many_lights" "points$n-cache-$cache" --scene builtin:gallery --scene "$GEN/points$n.gltf" \
        --set lpv.inject_cache=$cache
  done
  [ -n "${BASE:-}" ] && one "$BASE" "$OUT/many_lights-base" "points$n-base" --scene builtin:gallery --scene "$GEN/points$n.gltf"
done
# The gallery's own lights only (base cost of the frame).
one "$BENCH" "$OUT/many_lights" "gallery" --scene builtin:gallery

python3 - "$OUT/many_lights" ${BASE:+"$OUT/many_lights-base"} <<'PY'
import json, os, sys
print(f'{"run":26s} {"frame ms":>9s} {"lpv.inject":>10s} {"inject disp.":>12s} {"lpv.rsm":>8s} {"shadow.local":>12s} '
      f'{"faces inj.":>10s} {"from cache":>10s}')
for d in sys.argv[1:]:
    for name in sorted(os.listdir(d)):
        p = os.path.join(d, name, "results.json")
        if not os.path.exists(p): continue
        r = json.load(open(p))
        ms = {x["name"]: x["gpu_ms"]["median"] for x in r.get("passes", [])}
        disp = {x["name"]: x.get("dispatches", 0) for x in r.get("passes", [])}
        st = r.get("stats", {})
        frame = r.get("total_ms", 0)
        print(f'{name:26s} {frame:9.3f} {ms.get("lpv.inject", 0):10.3f} {disp.get("lpv.inject", 0):12.0f} '
              f'{ms.get("lpv.rsm", 0):8.3f} {ms.get("shadow.local", 0):12.3f} '
              f'{st.get("lpv.inject.local_faces_injected", "-")!s:>10s} {st.get("lpv.inject.local_faces_from_cache", "-")!s:>10s}')
PY
