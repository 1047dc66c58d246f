#!/bin/sh
# gpu-run-fma-ab.sh: the fifth pass's first GPU call: the BVH's slab tests as one fma per plane
# (SlabRay in glsl/lib/traverse_bvh.glsl) against the fourth pass's kernels (glsl/ at 0058e28),
# in turn, twice, on the issue's scenes at 1920x1080; the registers of both (--kernel-stats);
# the 4-wide nodes of both once; then the GPU tests with the new kernels. Expects
#   tools/bundle .bundle build/tests/test_layout build/tests/test_accel build/tests/test_stability
#       build/tests/test_render   (the test binaries then packed into .bundle/tests.tar.xz)
#   .bundle/scenes.tar.gz and .bundle/stadium/ (bench/gpu-prelude.sh, gpu-run-issue8.sh)
#   .bundle/variants/pass4/glsl   (git archive 0058e28 glsl | tar x -C .bundle/variants/pass4)
# Writes $OUT/fma-ab-log.txt and $OUT/fma-ab-json.tar.
. bench/gpu-prelude.sh
begin fma-ab
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
pass4="$root/.bundle/variants/pass4/glsl"
for round in 1 2; do
    run fma-$round 1920 1080 .bundle/vkrt bench $issue --accel bvh
    run pass4-$round 1920 1080 env VKRT_GLSL_DIR="$pass4" .bundle/vkrt bench $issue --accel bvh
done
run fma-kernel 1920 1080 .bundle/vkrt bench scenes/shared/bunny.cfg --accel bvh --kernel-stats
run pass4-kernel 1920 1080 env VKRT_GLSL_DIR="$pass4" .bundle/vkrt bench scenes/shared/bunny.cfg \
    --accel bvh --kernel-stats
run fma-width4 1920 1080 .bundle/vkrt bench $issue --accel bvh --bvh-width 4
run pass4-width4 1920 1080 env VKRT_GLSL_DIR="$pass4" .bundle/vkrt bench $issue --accel bvh --bvh-width 4
gpu_tests layout accel stability render
end fma-ab
