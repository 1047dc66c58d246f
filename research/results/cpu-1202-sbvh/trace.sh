#!/bin/sh
# Spatial splits (issue 21) on lavapipe: trace throughput of Sponza and Sibenik with the BVH
# without (--bvh-splits off) and with spatial splits (on), 160x120, four rounds, off first in odd
# rounds and on first in even ones (trace-*.json); auto's choice with its reason; then the
# traversal work per ray (--stats: nodes and triangles visited, independent of the machine's load)
# of the six scenes, with lavapipe's tree (leaves of 8, node cost 1) and with the GPUs' (leaves
# of 2, node cost 0.5: --bvh-leaf 2 --bvh-cost 0.5). Run from the
# repository root after `ninja -C build` and `tools/sliver_cylinder.py /tmp/sbvh/slivers`.
out=research/results/cpu-1202-sbvh
size="--width 160 --height 120"
for round in 1 2 3 4; do
    order="off on"
    [ $((round % 2)) = 0 ] && order="on off"
    for splits in $order; do
        echo "== round $round, bvh-splits $splits"
        # shellcheck disable=SC2086 # $size is four arguments
        nice build/vkrt bench scenes/shared/sponza.cfg scenes/shared/sibenik.cfg --accel bvh \
            --bvh-splits $splits $size --verbose --json $out/trace-$splits-$round.json
    done
done
all="scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/bunny.cfg
     scenes/shared/mori-sky.cfg scenes/shared/lost-empire.cfg /tmp/sbvh/slivers/scene.cfg"
echo "== bvh-splits auto"
# shellcheck disable=SC2086 # $all is six scenes, $size four arguments
nice build/vkrt bench $all --accel bvh $size --verbose
for splits in off on; do
    echo "== --stats, bvh-splits $splits"
    # shellcheck disable=SC2086
    nice build/vkrt bench $all --accel bvh --bvh-splits $splits $size --stats \
        --json $out/stats-$splits.json
    echo "== --stats, bvh-splits $splits, the GPUs' tree (--bvh-leaf 2 --bvh-cost 0.5)"
    # shellcheck disable=SC2086
    nice build/vkrt bench $all --accel bvh --bvh-splits $splits $size --stats \
        --bvh-leaf 2 --bvh-cost 0.5 --verbose --json $out/stats-gpu-tree-$splits.json
done
