#!/bin/sh
# gpu-run-tests.sh: the GPU tests on the GPU machine (an H100 without a display; no validation
# layers there). Expects the bundle made by
#   tools/bundle .bundle build/tests/test_materials build/tests/test_render \
#       build/tests/test_layout build/tests/test_stability build/tests/test_accel
#
# with .bundle/scenes.tar.gz holding the shared scenes' OBJ and MTL files under scenes/ and the
# teapot stadium (tools/teapot_stadium.py) under stadium/. Writes $OUT/tests.txt.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0 VKRT_SOURCE_DIR="$root" \
    VKRT_SCENES_DIR="$root/.bundle/scenes" VKRT_STADIUM_CFG="$root/.bundle/stadium/scene.cfg"
{ .bundle/vkrt --list-devices; nvidia-smi --query-gpu=name,driver_version --format=csv; } \
    >"$out/tests.txt" 2>&1
for t in layout render materials stability accel; do
    .bundle/bin/test_$t >/tmp/test_$t.txt 2>&1
    status=$?
    { echo "== test_$t exit $status"; cat /tmp/test_$t.txt; } >>"$out/tests.txt"
    echo "test_$t exit $status"
done
echo "== renders" >>"$out/tests.txt"
for s in scenes/cornell-spheres/scene.cfg scenes/materials-demo/scene.cfg; do
    .bundle/vkrt render "$s" --width 1920 --height 1080 -o /tmp/r.png 2>&1 | head -1 >>"$out/tests.txt"
done
tail -3 "$out/tests.txt"
