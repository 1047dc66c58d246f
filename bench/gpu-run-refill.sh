#!/bin/sh
# gpu-run-refill.sh: the sixth pass's second GPU call. The oracle orders (gpu-run-oracle.sh)
# showed idle lanes costing the big shadow dispatches 14-36%. Dynamic ray fetch
# (glsl/lib/trace_wave.glsl, --ray-fetch dynamic) refills idle lanes without knowing walks
# beforehand, and lost 10-40% in the first pass with a ballot at every step. This runs it with
# the ballot only every REFILL_EVERY steps (1, 4, 16) and a refill once 1/REFILL_SHARE of the
# subgroup is idle (2, 4) (bench/variants/refill-cadence.patch), against the committed default
# (one ray per invocation) in turn, twice, on issue 8's scenes at 1920x1080. Expects the bundle
# of gpu-run-oracle.sh and .bundle/variants/refill-kK-sS/glsl (glsl/ with the patch, the two
# constants set). Writes $OUT/refill-log.txt and $OUT/refill-json.tar.
. bench/gpu-prelude.sh
begin refill
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
for round in 1 2; do
    run static-$round 1920 1080 .bundle/vkrt bench $issue --accel bvh
    for k in 1 4 16; do
        for s in 2 4; do
            run k$k-s$s-$round 1920 1080 env VKRT_GLSL_DIR="$root/.bundle/variants/refill-k$k-s$s/glsl" \
                .bundle/vkrt bench $issue --accel bvh --ray-fetch dynamic
        done
    done
done
end refill
