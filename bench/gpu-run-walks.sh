#!/bin/sh
# gpu-run-walks.sh: the BVH's walks on the GPU machine in one call (docs/performance.md, fourth
# pass): the one-loop walk (the default on GPUs) after its refactoring into bvh_node_step, against
# the nested walk (the default on CPU devices) on both layouts; and the GPU tests, whose test_accel
# now holds both walks on both layouts to brute force. Expects the bundle (`tools/bundle .bundle
# build/tests/test_accel ...`, the test binaries in .bundle/tests.tar.xz, .bundle/scenes.tar.gz
# and the stadium scene in .bundle/stadium/, as for gpu-run-pass3.sh).
# Writes $OUT/walks-log.txt and $OUT/walks-json.tar.
. bench/gpu-prelude.sh
begin walks
gpu_tests layout accel stability render
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
run one-loop 1920 1080 .bundle/vkrt bench $issue --accel bvh
run nested 1920 1080 .bundle/vkrt bench $issue --accel bvh --walk nested
run nested-width4 1920 1080 .bundle/vkrt bench $issue --accel bvh --walk nested --bvh-width 4
run one-loop-width4 1920 1080 .bundle/vkrt bench $issue --accel bvh --bvh-width 4
run one-loop-again 1920 1080 .bundle/vkrt bench $issue --accel bvh
end walks
