#!/bin/sh
# gpu-run-pass2.sh: issue 8's measurements after its second pass, on the GPU machine in one call
# (docs/performance.md): the BVH of GPUs now has leaves of at most 2 triangles and a node cost of
# half a triangle test (src/render/accel_gpu.c).
#   1. the GPU tests of the bundle (no validation layers there);
#   2. vkrt bench and tools/rtpipe-bench of every scene with a scene file at 1920x1080, then
#      --stats, and the bunny and Sponza at 3840x2160;
#   3. the build's parameters around the new default, and the old default (leaves of 8, node
#      cost 1), in the same run;
#   4. the Whitted Sponza frame's profile (bench/gpu-run-whitted.sh).
# Expects `tools/bundle .bundle build/tests/test_...` with rtpipe-bench built, the test binaries
# moved into .bundle/tests.tar.xz, and .bundle/scenes.tar.gz (bench/gpu-prelude.sh).
# Writes $OUT/pass2-log.txt, $OUT/pass2-json.tar and what gpu-run-whitted.sh writes.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0 VKRT_SOURCE_DIR="$root" \
    VKRT_SCENES_DIR="$root/.bundle/scenes" VKRT_STADIUM_CFG="$root/.bundle/stadium/scene.cfg"
log="$out/pass2-log.txt"
json=/tmp/pass2-json
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
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
more="scenes/cornell/scene.cfg scenes/cornell-spheres/scene.cfg scenes/shared/cornell-original.cfg
      scenes/shared/teapot.cfg .bundle/stadium/scene.cfg"
run() { # name, width, height, command...: one run, its table into the log
    name=$1 w=$2 h=$3; shift 3
    echo "== $name ${w}x$h: $*" >>"$log"
    "$@" --width "$w" --height "$h" --json "$json/$name.json" 2>&1 | grep -v "Both .d." | tee -a "$log"
}
run vkrt 1920 1080 .bundle/vkrt bench $issue $more --accel bvh
run rtpipe 1920 1080 .bundle/rtpipe-bench $issue $more
run vkrt-stats 1920 1080 .bundle/vkrt bench $issue --accel bvh --stats
run vkrt-4k 3840 2160 .bundle/vkrt bench scenes/shared/bunny.cfg scenes/shared/sponza.cfg --accel bvh
run rtpipe-4k 3840 2160 .bundle/rtpipe-bench scenes/shared/bunny.cfg scenes/shared/sponza.cfg
run old-default 1920 1080 .bundle/vkrt bench $issue --accel bvh --bvh-leaf 8 --bvh-cost 1
run leaf1-cost0.5 1920 1080 .bundle/vkrt bench $issue --accel bvh --bvh-leaf 1 --bvh-cost 0.5
run leaf2-cost0.25 1920 1080 .bundle/vkrt bench $issue --accel bvh --bvh-leaf 2 --bvh-cost 0.25
run leaf3-cost0.75 1920 1080 .bundle/vkrt bench $issue --accel bvh --bvh-leaf 3 --bvh-cost 0.75
run vkrt-again 1920 1080 .bundle/vkrt bench $issue --accel bvh
tar cf "$out/pass2-json.tar" -C $json .
sh bench/gpu-run-whitted.sh >>"$log" 2>&1
nvidia-smi --query-gpu=clocks.sm,temperature.gpu,power.draw --format=csv >>"$log" 2>&1
