#!/bin/sh
# gpu-run-sponza-4k.sh: Sponza's shadow rays at 3840x2160 took 1.34 ms in the fifth pass's last
# call (pass5/final/vkrt-4k.json) against 0.60 ms in its second (pass5/vkrt-4k.json), the one
# change between them the triangle test's rows of fmas. This runs the committed kernels and the
# second call's (.bundle/variants/fma/glsl: git archive 37fbe1a~1 glsl) in turn, twice, on Sponza
# at 3840x2160 and 1920x1080. Writes $OUT/sponza-4k-log.txt and $OUT/sponza-4k-json.tar.
. bench/gpu-prelude.sh
begin sponza-4k
fma="$root/.bundle/variants/fma/glsl"
for round in 1 2; do
    run committed-4k-$round 3840 2160 .bundle/vkrt bench scenes/shared/sponza.cfg --accel bvh
    run fma-4k-$round 3840 2160 env VKRT_GLSL_DIR="$fma" .bundle/vkrt bench scenes/shared/sponza.cfg --accel bvh
done
run committed-1080 1920 1080 .bundle/vkrt bench scenes/shared/sponza.cfg --accel bvh
run fma-1080 1920 1080 env VKRT_GLSL_DIR="$fma" .bundle/vkrt bench scenes/shared/sponza.cfg --accel bvh
end sponza-4k
