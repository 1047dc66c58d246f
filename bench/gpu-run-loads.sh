#!/bin/sh
# gpu-run-loads.sh: the traversal reading triangles and BVH nodes through uniform texel buffers
# (`vkrt bench --loads texel`, the default on CPU devices) against storage buffers (the default
# elsewhere), on the GPU machine in one call (docs/performance.md). Also the GPU tests, with the
# default (storage) loads. Expects the bundle of gpu-run-pass3.sh (`tools/bundle .bundle
# build/tests/test_...`, the tests in .bundle/tests.tar.xz, .bundle/scenes.tar.gz).
# Writes $OUT/loads-log.txt and $OUT/loads-json.tar.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0 VKRT_SOURCE_DIR="$root" \
    VKRT_SCENES_DIR="$root/.bundle/scenes" VKRT_STADIUM_CFG="$root/.bundle/stadium/scene.cfg"
log="$out/loads-log.txt"
json=/tmp/loads-json
mkdir -p $json
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$log" 2>&1
gpu_tests layout accel stability render
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
run storage 1920 1080 .bundle/vkrt bench $issue --accel bvh --loads storage
run texel 1920 1080 .bundle/vkrt bench $issue --accel bvh --loads texel
run texel-width4 1920 1080 .bundle/vkrt bench $issue --accel bvh --loads texel --bvh-width 4
run storage-again 1920 1080 .bundle/vkrt bench $issue --accel bvh --loads storage
run texel-again 1920 1080 .bundle/vkrt bench $issue --accel bvh --loads texel
tar cf "$out/loads-json.tar" -C $json .
nvidia-smi --query-gpu=clocks.sm,temperature.gpu,power.draw --format=csv >>"$log" 2>&1
