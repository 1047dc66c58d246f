#!/bin/sh
# gpu-run-issue8.sh: issue 8's measurements on the GPU machine in one call (docs/performance.md):
#   1. the GPU tests of the bundle (no validation layers there);
#   2. vkrt bench (BVH, 1920x1080) of every scene with a scene file, for the per-scene table and
#      the chart of rays per second against triangles; then --stats (nodes, triangles, SIMD
#      utilisation) and --whole-scene (materials and textures loaded, as a render loads them);
#   3. tools/rtpipe-bench, the driver's own VK_KHR_ray_tracing_pipeline, on the same scenes and rays;
#   4. the Whitted Sponza frame's profile (bench/gpu-run-whitted.sh).
# Expects `tools/bundle .bundle build/tests/test_...` with rtpipe-bench built
# (meson -Drtpipe_bench=true), the test binaries moved into .bundle/tests.tar.xz (they are most
# of the bundle, and a call carries 64 MiB), and .bundle/scenes.tar.gz (bench/gpu-prelude.sh). Writes
# $OUT/issue8-log.txt, $OUT/issue8-json.tar and what gpu-run-whitted.sh writes.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0 VKRT_SOURCE_DIR="$root" \
    VKRT_SCENES_DIR="$root/.bundle/scenes" VKRT_STADIUM_CFG="$root/.bundle/stadium/scene.cfg"
log="$out/issue8-log.txt"
json=/tmp/issue8-json
mkdir -p $json
[ -f .bundle/tests.tar.xz ] && tar xJf .bundle/tests.tar.xz -C .bundle/bin
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$log" 2>&1
for t in layout render accel stability materials; do
    [ -x .bundle/bin/test_$t ] || continue
    timeout 300 .bundle/bin/test_$t >/tmp/test_$t.txt 2>&1
    status=$?
    { echo "== test_$t exit $status"; tail -3 /tmp/test_$t.txt; } >>"$log"
    echo "test_$t exit $status"
done
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
run vkrt-stats .bundle/vkrt bench $issue --accel bvh --stats
run vkrt-whole .bundle/vkrt bench $issue --accel bvh --whole-scene
run vkrt-width4 .bundle/vkrt bench $issue --accel bvh --bvh-width 4
run vkrt-again .bundle/vkrt bench $issue --accel bvh
run rtpipe-again .bundle/rtpipe-bench $issue
tar cf "$out/issue8-json.tar" -C $json .
[ -f bench/gpu-run-whitted.sh ] && sh bench/gpu-run-whitted.sh >>"$log" 2>&1
nvidia-smi --query-gpu=clocks.sm,temperature.gpu,power.draw --format=csv >>"$log" 2>&1
