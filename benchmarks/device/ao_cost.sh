#!/usr/bin/env bash
# AO chain cost of issue 25 per configuration and named view, without a
# reference in the process (the ao-front sweep's timings were erratic): 1080p,
# 200 frames after 100, LPV and SSR off, two repetitions; prints the AO chain
# (every ao.* pass plus visibility.layer2) per repetition. The errors of the
# same configurations come from ao_front.sh.
# Run from the repo root with BENCH, OUT and SCENES set.
set -uo pipefail
BENCH=${BENCH:-./build/rtgi-bench}
OUT=${OUT:-out}
SCENES=${SCENES:-../shared/scenes}
C=(--res 1920x1080 --frames 200 --warmup 100 --no-images --set lpv=off --set ssr=off --set ao.directional=off)
"$BENCH" --scene builtin:atrium "${C[@]}" --out "$OUT/ao_cost/warm" >/dev/null 2>&1  # GPU clocks up
for rep in 1 2; do
  for cfg in "ao=rtao ao.rays=1" "ao=rtao ao.rays=1 ao.blur=off" "ao=gtao" "ao=vbao" "ao=vbao ao.second_layer=on"; do
    set_=(); for kv in $cfg; do set_+=(--set "$kv"); done
    tag=${cfg// /+}
    for sv in "builtin:atrium court 1.0" "builtin:atrium arcade 1.0" "builtin:atrium gallery 1.0" \
              "builtin:restaurant entrance 0.3" "builtin:restaurant table 0.3" \
              "dragon front 0.4" "dragon side 0.4" "dragon top 0.4"; do
      read -r sc view rad <<<"$sv"
      if [ "$sc" = dragon ]; then scn=(--scene builtin:plane --scene "$SCENES/stanford-dragon/dragon.gltf"); lab=dragon
      else scn=(--scene "$sc"); lab=${sc#builtin:}; fi
      "$BENCH" "${scn[@]}" "${C[@]}" --set view="$view" --set ao.radius="$rad" "${set_[@]}" \
        --out "$OUT/ao_cost/$rep/$tag/$lab-$view" >/dev/null 2>&1 || echo "FAILED $tag $lab $view"
    done
  done
done
python3 - "$OUT/ao_cost" <<'PY'
import collections, glob, json, os, sys
rows = collections.defaultdict(dict)
for f in glob.glob(os.path.join(sys.argv[1], "[12]", "*", "*", "results.json")):
    rep, tag, view = f.split(os.sep)[-4:-1]
    r = json.load(open(f))
    rows[(tag, view)][rep] = sum(p["gpu_ms"]["median"] for p in r["passes"]
                                 if p["name"].startswith("ao.") or p["name"] == "visibility.layer2")
for k in sorted(rows):
    print("%-36s %-22s %s" % (k[0], k[1], " ".join("%.3f" % rows[k][r] for r in sorted(rows[k]))))
PY
