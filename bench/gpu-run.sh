#!/bin/sh
# gpu-run.sh: what was run on the GPU machine (an H100 without a display) to produce
# bench/results/*-h100.*. It expects the bundle made by
#   tools/bundle .bundle build/tests/test_accel build/tests/test_render build/tests/test_layout build/tests/test_intersect
# with .bundle/scenes.tar.gz holding the shared scenes' OBJ and MTL files (scenes/, the stadium
# from tools/teapot_stadium.py in stadium/), and writes everything under $OUT.
set -u
out=${OUT:-/tmp/vkrt-out}
mkdir -p "$out"
root=$(pwd)
(cd .bundle && tar xzf scenes.tar.gz)
mkdir -p ../shared && ln -sfn "$root/.bundle/scenes" ../shared/scenes
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0 VKRT_SOURCE_DIR="$root" \
    VKRT_SCENES_DIR="$root/.bundle/scenes" VKRT_STADIUM_CFG="$root/.bundle/stadium/scene.cfg"
{ .bundle/vkrt --list-devices; nvidia-smi -L; nvidia-smi --query-gpu=driver_version --format=csv; } \
    >"$out/devices.txt" 2>&1
# Correctness first: the GPU tests (no validation layers on that machine).
for t in layout intersect render accel; do
    .bundle/bin/test_$t >/tmp/test_$t.txt 2>&1
    status=$?
    { echo "== test_$t exit $status"; cat /tmp/test_$t.txt; } >>"$out/tests.txt"
    echo "test_$t exit $status"
done
.bundle/vkrt bench scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg \
    scenes/shared/lost-empire.cfg scenes/shared/teapot.cfg .bundle/stadium/scene.cfg \
    --width 1920 --height 1080 --json "$out/bench-h100.json" | tee "$out/bench-h100.txt"
.bundle/vkrt render scenes/shared/sponza.cfg -o "$out/sponza-h100.png" --verbose 2>&1 |
    grep -v "Both .d." | tee "$out/render-h100.txt"
# The grid's density (cells per triangle), measured rather than guessed.
for density in 0.5 1 2 4 8; do
    .bundle/vkrt bench scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg \
        scenes/shared/lost-empire.cfg scenes/shared/teapot.cfg --accel grid --grid-density $density \
        --width 1920 --height 1080 --json "/tmp/density-$density.json" >/dev/null
done
python3 - "$out" <<'PY' | tee "$out/density-h100.txt"
import json, sys
out = sys.argv[1]
runs = {d: json.load(open(f"/tmp/density-{d}.json")) for d in ["0.5", "1", "2", "4", "8"]}
json.dump(runs, open(f"{out}/density-h100.json", "w"), indent=1)
print("density  scene                          primary Mrays/s  shadow Mrays/s  MiB")
for d, run in runs.items():
    for r in run["results"]:
        print(f"{d:>7}  {r['scene']:<30} {r['primary_mrays_per_s']:>15.0f} {r['shadow_mrays_per_s']:>15.0f} {r['bytes']/2**20:>5.2f}")
PY
