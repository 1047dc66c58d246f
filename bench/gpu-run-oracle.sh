#!/bin/sh
# gpu-run-oracle.sh: the sixth pass's GPU call on issue 8's one GPU target still missed, the
# bunny's shadow rays at 1920x1080. Its dispatch ends with its longest subgroups
# (docs/performance.md, third pass); this measures what the best order of the same rays could
# give the committed walk, with orders no renderer could know before tracing (oracles): the
# variant's occlusion kernel reports each ray's loop iterations, and vkrt bench, with
# VKRT_SHADOW_ORACLE set, times the same shadow rays again in order, with their subgroups
# reversed, longest first, and with the rays themselves sorted longest first
# (bench/variants/shadow-oracle.patch). Expects
#   .bundle/vkrt               tools/bundle of the commit (committed kernels)
#   .bundle/bin/vkrt-oracle    vkrt built with the patch's src/bench.c and the committed glsl/
#   .bundle/variants/oracle/glsl   glsl/ with the patch applied
#   .bundle/scenes.tar.gz      the four scenes of ../shared/scenes
# Writes $OUT/oracle-log.txt and $OUT/oracle-json.tar.
. bench/gpu-prelude.sh
begin oracle
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
oracle() {
    env VKRT_SHADOW_ORACLE=1 VKRT_GLSL_DIR="$root/.bundle/variants/oracle/glsl" \
        .bundle/bin/vkrt-oracle "$@"
}
run committed 1920 1080 .bundle/vkrt bench $issue --accel bvh
run oracle-1080 1920 1080 oracle bench $issue --accel bvh
run oracle-1440 2560 1440 oracle bench scenes/shared/bunny.cfg --accel bvh
run oracle-4k 3840 2160 oracle bench scenes/shared/bunny.cfg --accel bvh
run committed-again 1920 1080 .bundle/vkrt bench $issue --accel bvh
end oracle
