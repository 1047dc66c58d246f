#!/bin/sh
# gpu-run-walks-final.sh: the fourth pass's last GPU call: the GPU tests and the issue's scenes
# with the kernels as committed (the one-loop walk back on a stack of its own, after
# gpu-run-walks-ab.sh). Expects the bundle of gpu-run-walks.sh.
# Writes $OUT/final-log.txt and $OUT/final-json.tar.
. bench/gpu-prelude.sh
begin final
gpu_tests layout accel stability render
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
run final 1920 1080 .bundle/vkrt bench $issue --accel bvh
run final-nested 1920 1080 .bundle/vkrt bench $issue --accel bvh --walk nested
end final
