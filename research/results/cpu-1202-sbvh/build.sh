#!/bin/sh
# Spatial splits (issue 21): SAH cost, references and build time of the BVH with splits off
# (budget 0) and on (budget 0.3, `bvh-splits on`), at the CPU device's settings (leaf 8, node cost 1)
# and the GPU's (leaf 2, node cost 0.5, src/render/tuning.c), two threads, 5 runs each, off and on
# in turn. Run from the repository root after `ninja -C build`; the sliver scene is
# tools/sliver_cylinder.py's (96,002 triangles): `tools/sliver_cylinder.py /tmp/sbvh/slivers`.
S=${VKRT_SCENES_DIR:-../shared/scenes}
for obj in $S/dabrovic-sponza/sponza.obj $S/sibenik-cathedral/sibenik.obj \
           $S/stanford-bunny/stanford-bunny.obj $S/mori-knob/testObj.obj \
           $S/lost-empire/lost_empire.obj /tmp/sbvh/slivers/slivers.obj; do
    for settings in "0 0" "2 0.5"; do
        for budget in 0 0.3; do
            echo "== $obj leaf/cost $settings budget $budget"
            # shellcheck disable=SC2086 # $settings is two arguments
            nice build/bvh-bench "$obj" 5 2 $settings $budget | tail -2
        done
    done
done
