#!/bin/sh
# gpu-run-sah.sh: the BVH build's SAH parameters against the trace on the GPU machine: vkrt bench
# of the four issue-8 scenes at 1920x1080 with the default build (leaves of at most 8, a node
# costing one triangle test) and with other node costs and leaf sizes (--bvh-cost, --bvh-leaf),
# the default first and last; then --stats of the two that differ most. Expects .bundle from
# tools/bundle and .bundle/scenes.tar.gz. Writes $OUT/sah-log.txt and $OUT/sah-json.tar.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0
log="$out/sah-log.txt"
json=/tmp/sah-json
mkdir -p $json
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$log" 2>&1
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
run() { # name, command...: one run, its table into the log
    name=$1; shift
    echo "== $name: $*" >>"$log"
    "$@" --width 1920 --height 1080 --json "$json/$name.json" 2>&1 | grep -v "Both .d." | tee -a "$log"
}
run default .bundle/vkrt bench $issue --accel bvh
run cost0.5 .bundle/vkrt bench $issue --accel bvh --bvh-cost 0.5
run cost2 .bundle/vkrt bench $issue --accel bvh --bvh-cost 2
run cost3 .bundle/vkrt bench $issue --accel bvh --bvh-cost 3
run leaf4 .bundle/vkrt bench $issue --accel bvh --bvh-leaf 4
run leaf16-cost2 .bundle/vkrt bench $issue --accel bvh --bvh-leaf 16 --bvh-cost 2
run leaf2-cost0.5 .bundle/vkrt bench $issue --accel bvh --bvh-leaf 2 --bvh-cost 0.5
run default-again .bundle/vkrt bench $issue --accel bvh
run stats-cost0.5 .bundle/vkrt bench $issue --accel bvh --bvh-cost 0.5 --stats
run stats-cost3 .bundle/vkrt bench $issue --accel bvh --bvh-cost 3 --stats
tar cf "$out/sah-json.tar" -C $json .
