#!/bin/sh
# gpu-run-issue8-chart.sh: the points of docs/performance.md's chart of rays per second against
# triangles on the GPU machine: vkrt bench (BVH) and tools/rtpipe-bench over every scene with a
# scene file, 1920x1080; then the bunny and Sponza at 3840x2160 (four times the rays per
# dispatch: does the bunny's small shadow dispatch cost its rate?). Expects the bundle of
# bench/gpu-run-issue8.sh. Writes $OUT/chart-log.txt and $OUT/chart-json.tar.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib"
log="$out/chart-log.txt"
json=/tmp/chart-json
mkdir -p $json
scenes="scenes/cornell/scene.cfg scenes/shared/cornell-original.cfg scenes/cornell-spheres/scene.cfg
        scenes/shared/teapot.cfg .bundle/stadium/scene.cfg scenes/shared/sponza.cfg
        scenes/shared/bunny.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
run() { # name, width, height, command...
    name=$1 w=$2 h=$3; shift 3
    echo "== $name ${w}x$h: $*" >>"$log"
    "$@" --width "$w" --height "$h" --json "$json/$name.json" 2>&1 | grep -v "Both .d." | tee -a "$log"
}
run vkrt 1920 1080 .bundle/vkrt bench $scenes --accel bvh
run rtpipe 1920 1080 .bundle/rtpipe-bench $scenes
run vkrt-4k 3840 2160 .bundle/vkrt bench scenes/shared/bunny.cfg scenes/shared/sponza.cfg --accel bvh
run rtpipe-4k 3840 2160 .bundle/rtpipe-bench scenes/shared/bunny.cfg scenes/shared/sponza.cfg
tar cf "$out/chart-json.tar" -C $json .
