#!/usr/bin/env bash
# Area lights and soft shadows of issue 26 (docs/lights.md "Area shading",
# "Penumbrae"): the cost per light at 1080p of the direct pass's polygonal
# area shading and of the PCSS soft shadows, as differences of the `direct`
# pass time between runs that differ in one thing only:
#   cornell-nolight   emissive.lights=off          (no local light at all)
#   cornell-unshadowed passes.off=shadow.local     (area shading, no shadow lookup)
#   cornell-soft      defaults                     (area shading + PCSS, 16 + 16 taps)
#   gallery-hard      light.radius=0               (3 lights, 3x3 PCF each)
#   gallery-soft      light.radius=0.05            (3 lights, PCSS each)
#   gallery-unshadowed passes.off=shadow.local
# area shading per light = direct(cornell-unshadowed) − direct(cornell-nolight);
# soft shadow per light  = direct(cornell-soft) − direct(cornell-unshadowed);
# PCSS vs PCF per light  = (direct(gallery-soft) − direct(gallery-hard)) / 3.
# Then the classic Cornell box view against the path tracer (acceptance,
# 480x270, 4096 paths, direct/indirect split).
# Run from the repo root with BENCH, OUT and SCENES set.
set -euo pipefail
BENCH=${BENCH:-./build/rtgi-bench}
OUT=${OUT:-out}
SCENES=${SCENES:-../shared/scenes}
CORNELL="$SCENES/cornell-box/cornell-box.gltf"
COMMON=(--res 1920x1080 --frames 100 --warmup 20 --no-images)
mkdir -p "$OUT/arealights"
run() {
  local name=$1; shift
  "$BENCH" "$@" "${COMMON[@]}" --out "$OUT/arealights/$name"
}
run cornell-nolight --scene "$CORNELL" --set view=front --set emissive.lights=off
run cornell-unshadowed --scene "$CORNELL" --set view=front --set passes.off=shadow.local
run cornell-soft --scene "$CORNELL" --set view=front
run gallery-hard --scene builtin:gallery --set light.radius=0
run gallery-soft --scene builtin:gallery --set light.radius=0.05
run gallery-unshadowed --scene builtin:gallery --set passes.off=shadow.local
python3 - "$OUT/arealights" <<'PY'
import json, sys, os
d = sys.argv[1]
def ms(name, p="direct"):
    r = json.load(open(os.path.join(d, name, "results.json")))
    return next(x for x in r["passes"] if x["name"] == p)["gpu_ms"]["median"]
for n in ("cornell-nolight", "cornell-unshadowed", "cornell-soft", "gallery-hard", "gallery-soft", "gallery-unshadowed"):
    print("%-20s direct %.3f ms" % (n, ms(n)))
print("area shading per light  %.3f ms" % (ms("cornell-unshadowed") - ms("cornell-nolight")))
print("soft shadow per light   %.3f ms" % (ms("cornell-soft") - ms("cornell-unshadowed")))
print("PCSS - PCF per light    %.3f ms" % ((ms("gallery-soft") - ms("gallery-hard")) / 3))
PY
# Acceptance: the classic view against the path tracer.
"$BENCH" --scene "$CORNELL" --set view=front --res 480x270 --frames 20 --warmup 10 --reference \
  --set reference=full --set reference.spp=4096 --set reference.split=on --out "$OUT/arealights/cornell-front-ref"
python3 -c "import json,sys; e=json.load(open('$OUT/arealights/cornell-front-ref/results.json'))['error']; \
print('interior rel RMSE', e['interior']['rel_rmse'], 'bias', e['interior']['bias'], \
'direct', e['split']['direct']['interior']['rel_rmse'], 'indirect', e['split']['indirect']['interior']['rel_rmse'])"
