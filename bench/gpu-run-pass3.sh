#!/bin/sh
# gpu-run-pass3.sh: issue 8's third pass, on the GPU machine in one call (docs/performance.md):
# the pairs walk as "while-while" (inner nodes in one loop, leaves in another; Aila and Laine
# 2009), against the one loop with a branch each, and the shadow dispatch in reverse order, the
# experiment that tests tools/walk_profile.c's account of the bunny's small dispatch.
#   1. the GPU tests with the while-while kernels (no validation layers there);
#   2. vkrt bench of the issue's four scenes at 1920x1080: the default kernels, the while-while
#      walk with and without speculation (VKRT_GLSL_DIR variants), the reversed shadow dispatch;
#      --stats of the default and the while-while walk; the bunny and Sponza at 3840x2160;
#   3. the driver's pipeline on the same rays, and the other scenes, for the tables;
#   4. the Whitted Sponza frame's profile with each walk (bench/gpu-run-whitted.sh);
#   5. the default kernels again, for drift.
# Expects `tools/bundle .bundle build/tests/test_...` with rtpipe-bench built, the test binaries in
# .bundle/tests.tar.xz, .bundle/scenes.tar.gz (bench/gpu-prelude.sh) and the kernel variants in
# .bundle/variants/NAME, each glsl/ with bench/variants/NAME.patch applied:
#   for v in while-while while-while-plain shadow-reversed; do
#     rm -rf /tmp/v && mkdir -p /tmp/v .bundle/variants && cp -r glsl /tmp/v/ &&
#     patch -s -p1 -d /tmp/v <bench/variants/$v.patch && rm -rf .bundle/variants/$v &&
#     cp -r /tmp/v/glsl .bundle/variants/$v; done
# (while-while-plain: the same walk with SPECULATIVE_LEAVES false.)
# Writes $OUT/pass3-log.txt, $OUT/pass3-json.tar and the Whitted profiles in $OUT/{default,ww}/.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0 VKRT_SOURCE_DIR="$root" \
    VKRT_SCENES_DIR="$root/.bundle/scenes" VKRT_STADIUM_CFG="$root/.bundle/stadium/scene.cfg"
log="$out/pass3-log.txt"
json=/tmp/pass3-json
mkdir -p $json
ww="$root/.bundle/variants/while-while"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$log" 2>&1
VKRT_GLSL_DIR="$ww" gpu_tests accel stability render
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
more="scenes/cornell/scene.cfg scenes/cornell-spheres/scene.cfg scenes/shared/cornell-original.cfg
      scenes/shared/teapot.cfg .bundle/stadium/scene.cfg"
run vkrt 1920 1080 .bundle/vkrt bench $issue --accel bvh
VKRT_GLSL_DIR="$ww" run ww 1920 1080 .bundle/vkrt bench $issue --accel bvh
VKRT_GLSL_DIR="$root/.bundle/variants/while-while-plain" run ww-plain 1920 1080 .bundle/vkrt bench $issue --accel bvh
VKRT_GLSL_DIR="$root/.bundle/variants/shadow-reversed" run reversed 1920 1080 .bundle/vkrt bench $issue --accel bvh
run vkrt-stats 1920 1080 .bundle/vkrt bench $issue --accel bvh --stats
VKRT_GLSL_DIR="$ww" run ww-stats 1920 1080 .bundle/vkrt bench $issue --accel bvh --stats
VKRT_GLSL_DIR="$ww" run ww-4k 3840 2160 .bundle/vkrt bench scenes/shared/bunny.cfg scenes/shared/sponza.cfg --accel bvh
run rtpipe 1920 1080 .bundle/rtpipe-bench $issue $more
VKRT_GLSL_DIR="$ww" run ww-more 1920 1080 .bundle/vkrt bench $more --accel bvh
run vkrt-more 1920 1080 .bundle/vkrt bench $more --accel bvh
tar cf "$out/pass3-json.tar" -C $json .
OUT="$out/default" sh bench/gpu-run-whitted.sh >>"$log" 2>&1
VKRT_GLSL_DIR="$ww" OUT="$out/ww" sh bench/gpu-run-whitted.sh >>"$log" 2>&1
run vkrt-again 1920 1080 .bundle/vkrt bench $issue --accel bvh
VKRT_GLSL_DIR="$ww" run ww-again 1920 1080 .bundle/vkrt bench $issue --accel bvh
tar cf "$out/pass3-json.tar" -C $json .
nvidia-smi --query-gpu=clocks.sm,temperature.gpu,power.draw --format=csv >>"$log" 2>&1
