#!/bin/sh
# gpu-run-pass5.sh: the fifth pass's second GPU call: every GPU yardstick of issue 8 in one run,
# with the kernels as committed (the slab tests as one fma per plane, after gpu-run-fma-ab.sh):
#   1. vkrt bench (BVH) and tools/rtpipe-bench, the driver's VK_KHR_ray_tracing_pipeline, on every
#      scene with a scene file at 1920x1080 (the per-scene table and the chart), then the issue's
#      four scenes once more each, after the other's run;
#   2. vkrt bench --stats (nodes, triangles, SIMD utilisation per ray kind);
#   3. the bunny and Sponza at 3840x2160 in both tracers (the bunny's small shadow dispatch);
#   4. the Whitted Sponza frame's profile (bench/gpu-run-whitted.sh).
# The BVH build times are in vkrt bench's JSON (build_ms, on the GPU machine's CPU). Expects the
# bundle of gpu-run-fma-ab.sh with rtpipe-bench (meson -Drtpipe_bench=true). Writes
# $OUT/NAME-log.txt, $OUT/NAME-json.tar, and what gpu-run-whitted.sh writes.
#   sh bench/gpu-run-pass5.sh [NAME]
# NAME is pass5 by default (the second call); given (the last call, `final`, with the triangle
# test's rows of fmas committed and a new bundle), the GPU tests run first.
. bench/gpu-prelude.sh
begin ${1:-pass5}
[ $# -gt 0 ] && gpu_tests layout accel stability render
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
more="scenes/cornell/scene.cfg scenes/cornell-spheres/scene.cfg scenes/shared/cornell-original.cfg
      scenes/shared/teapot.cfg .bundle/stadium/scene.cfg"
run vkrt 1920 1080 .bundle/vkrt bench $issue $more --accel bvh
run rtpipe 1920 1080 .bundle/rtpipe-bench $issue $more
run vkrt-again 1920 1080 .bundle/vkrt bench $issue --accel bvh
run rtpipe-again 1920 1080 .bundle/rtpipe-bench $issue
run vkrt-stats 1920 1080 .bundle/vkrt bench $issue --accel bvh --stats
run vkrt-4k 3840 2160 .bundle/vkrt bench scenes/shared/bunny.cfg scenes/shared/sponza.cfg --accel bvh
run rtpipe-4k 3840 2160 .bundle/rtpipe-bench scenes/shared/bunny.cfg scenes/shared/sponza.cfg
end ${1:-pass5}
sh bench/gpu-run-whitted.sh >>"$log" 2>&1
