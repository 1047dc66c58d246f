#!/bin/sh
# gpu-run-sort.sh: the second pass at issue 8 on the GPU machine, in one call
# (docs/performance.md, "Issue 8, second pass"):
#   1. the GPU tests of the bundle, test_ray_sort among them (no validation layers there);
#   2. vkrt bench and tools/rtpipe-bench of every scene with a scene file at 1920x1080, the
#      driver's pipeline and vkrt in the same run;
#   3. diffuse rays sorted by direction on the GPU (vkrt bench --sort-diffuse 4 and 8: the sort's
#      time included), and the driver's pipeline on the same order (rtpipe-bench --sort-diffuse 8,
#      ordered on the host, its sort not timed);
#   4. the driver's statistics of vkrt's trace kernels (--kernel-stats: registers and the like).
# Expects `tools/bundle .bundle build/tests/test_...` with rtpipe-bench built, the test binaries
# moved into .bundle/tests.tar.xz, and .bundle/scenes.tar.gz (bench/gpu-prelude.sh).
# Writes $OUT/sort-log.txt and $OUT/sort-json.tar.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0 VKRT_SOURCE_DIR="$root" \
    VKRT_SCENES_DIR="$root/.bundle/scenes" VKRT_STADIUM_CFG="$root/.bundle/stadium/scene.cfg"
log="$out/sort-log.txt"
json=/tmp/sort-json
mkdir -p $json
[ -f .bundle/tests.tar.xz ] && tar xJf .bundle/tests.tar.xz -C .bundle/bin
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$log" 2>&1
for t in layout ray_sort render accel stability materials; do
    [ -x .bundle/bin/test_$t ] || continue
    timeout 300 .bundle/bin/test_$t >/tmp/test_$t.txt 2>&1
    status=$?
    { echo "== test_$t exit $status"; tail -3 /tmp/test_$t.txt; } >>"$log"
    echo "test_$t exit $status"
done
grep "cells" /tmp/test_ray_sort.txt >>"$log"
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
more="scenes/cornell/scene.cfg scenes/cornell-spheres/scene.cfg scenes/shared/cornell-original.cfg
      scenes/shared/teapot.cfg .bundle/stadium/scene.cfg"
run() { # name, command...: one run, its table into the log
    name=$1; shift
    echo "== $name: $*" >>"$log"
    "$@" --width 1920 --height 1080 --json "$json/$name.json" 2>&1 | grep -v "Both .d." | tee -a "$log"
}
run vkrt .bundle/vkrt bench $issue $more --accel bvh
run rtpipe .bundle/rtpipe-bench $issue $more
run vkrt-sort4 .bundle/vkrt bench $issue --accel bvh --sort-diffuse 4
run vkrt-sort8 .bundle/vkrt bench $issue --accel bvh --sort-diffuse 8
run rtpipe-sort8 .bundle/rtpipe-bench $issue --sort-diffuse 8
run vkrt-kernel .bundle/vkrt bench $issue --accel bvh --kernel-stats
run vkrt-again .bundle/vkrt bench $issue --accel bvh
tar cf "$out/sort-json.tar" -C $json .
nvidia-smi --query-gpu=clocks.sm,temperature.gpu,power.draw --format=csv >>"$log" 2>&1
