#!/bin/sh
# gpu-run-walks-ab.sh: the GPU's default walk (pairs, one loop) as refactored in the fourth pass
# against the third pass's kernels (glsl/ at 9301c96) and against the refactored walk with the
# old loop and a stack local to the function (.bundle/variants/local), in turn, twice, in one
# call: whether the refactoring cost time. Expects the bundle of gpu-run-walks.sh and
#   .bundle/variants/pass3/glsl   (git archive 9301c96 glsl | tar x -C .bundle/variants/pass3)
#   .bundle/variants/local/glsl   (the variant, kept as bench/variants/one-loop-local-stack.patch)
# Writes $OUT/walks-ab-log.txt and $OUT/walks-ab-json.tar.
. bench/gpu-prelude.sh
begin walks-ab
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
for round in 1 2; do
    run refactored-$round 1920 1080 .bundle/vkrt bench $issue --accel bvh
    run pass3-$round 1920 1080 env VKRT_GLSL_DIR="$root/.bundle/variants/pass3/glsl" .bundle/vkrt bench $issue --accel bvh
    run local-$round 1920 1080 env VKRT_GLSL_DIR="$root/.bundle/variants/local/glsl" .bundle/vkrt bench $issue --accel bvh
done
end walks-ab
