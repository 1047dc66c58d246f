#!/bin/sh
# gpu-run-float-quads.sh: the 4-wide BVH with float boxes (128-byte nodes, no decoding; shadow
# rays push the children hit unsorted) against the pairs, on the GPU machine in one call
# (docs/performance.md, third pass). .bundle/vkrt-fq is vkrt built with
# bench/variants/float-quads.patch applied (C and GLSL), where `--bvh-width 4` is that layout;
# .bundle/variants/float-quads-nearest is its glsl/ with float-quads-nearest.patch applied
# (closest-hit rays put only the nearest child first). Expects the bundle of gpu-run-pass3.sh,
# and vkrt-fq made beside it by
#   git apply bench/variants/float-quads.patch && ninja -C build &&
#   cp build/vkrt .bundle/bin/vkrt-fq && strip --strip-unneeded .bundle/bin/vkrt-fq &&
#   sed 's/bin\/vkrt"/bin\/vkrt-fq"/' .bundle/vkrt >.bundle/vkrt-fq && chmod +x .bundle/vkrt-fq &&
#   git apply -R bench/variants/float-quads.patch && ninja -C build
# and the nearest-first variant: a copy of the patched glsl/ with float-quads-nearest.patch
# applied inside it (patch -p1 -d COPY <bench/variants/float-quads-nearest.patch).
# Writes $OUT/fq-log.txt and $OUT/fq-json.tar.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0
log="$out/fq-log.txt"
json=/tmp/fq-json
mkdir -p $json
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$log" 2>&1
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
more="scenes/cornell/scene.cfg scenes/cornell-spheres/scene.cfg scenes/shared/cornell-original.cfg
      scenes/shared/teapot.cfg .bundle/stadium/scene.cfg"
run pairs 1920 1080 .bundle/vkrt bench $issue --accel bvh
run fq 1920 1080 .bundle/vkrt-fq bench $issue --accel bvh --bvh-width 4
VKRT_GLSL_DIR="$root/.bundle/variants/float-quads-nearest" \
    run fq-nearest 1920 1080 .bundle/vkrt-fq bench $issue --accel bvh --bvh-width 4
run fq-stats 1920 1080 .bundle/vkrt-fq bench $issue --accel bvh --bvh-width 4 --stats
run fq-4k 3840 2160 .bundle/vkrt-fq bench scenes/shared/bunny.cfg scenes/shared/sponza.cfg --accel bvh --bvh-width 4
run pairs-4k 3840 2160 .bundle/vkrt bench scenes/shared/bunny.cfg scenes/shared/sponza.cfg --accel bvh
run fq-more 1920 1080 .bundle/vkrt-fq bench $more --accel bvh --bvh-width 4
run pairs-more 1920 1080 .bundle/vkrt bench $more --accel bvh
run fq-leaf4 1920 1080 .bundle/vkrt-fq bench $issue --accel bvh --bvh-width 4 --bvh-leaf 4 --bvh-cost 1
run pairs-again 1920 1080 .bundle/vkrt bench $issue --accel bvh
run fq-again 1920 1080 .bundle/vkrt-fq bench $issue --accel bvh --bvh-width 4
tar cf "$out/fq-json.tar" -C $json .
nvidia-smi --query-gpu=clocks.sm,temperature.gpu,power.draw --format=csv >>"$log" 2>&1
