#!/bin/sh
# gpu-run-shear-rows.sh: the fifth pass's last GPU calls: the watertight triangle test with its
# per-ray permutation and shear as rows of fmas, against the committed kernels, in turn, twice, on
# the issue's scenes at 1920x1080; the registers (--kernel-stats); then the GPU tests with the
# last variant named. Expects the bundle of gpu-run-fma-ab.sh and, per variant NAME given,
#   .bundle/variants/NAME/glsl   (glsl/ with the variant's patch applied)
# The first call ran `sh bench/gpu-run-shear-rows.sh rows` (bench/variants/shear-rows.patch, the
# rows written through a per-ray index); the second `... rows onehot`
# (bench/variants/shear-rows-onehot.patch, the rows made from one-hot axes). Writes
# $OUT/shear-rows-log.txt and $OUT/shear-rows-json.tar.
. bench/gpu-prelude.sh
begin shear-rows
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
# The loops' variable is not `name`: run (bench/gpu-prelude.sh) sets that one. In the second call
# it was, so the tests looked for .bundle/variants/onehot-kernel and failed to start; they are
# not counted (docs/performance.md), and the last call (gpu-run-pass5.sh final) ran them.
for round in 1 2; do
    run committed-$round 1920 1080 .bundle/vkrt bench $issue --accel bvh
    for variant in "$@"; do
        run $variant-$round 1920 1080 env VKRT_GLSL_DIR="$root/.bundle/variants/$variant/glsl" \
            .bundle/vkrt bench $issue --accel bvh
    done
done
for variant in "$@"; do
    run $variant-kernel 1920 1080 env VKRT_GLSL_DIR="$root/.bundle/variants/$variant/glsl" \
        .bundle/vkrt bench scenes/shared/bunny.cfg --accel bvh --kernel-stats
    last=$variant
done
VKRT_GLSL_DIR="$root/.bundle/variants/$last/glsl" gpu_tests layout accel stability render
end shear-rows
