#!/bin/sh
# gpu-run-scaling.sh: tools/chart --scaling's renders on the GPU machine: every scene at
# 1920 pixels wide, 1 spp, with each structure, the fastest of three `vkrt render` runs (their
# summary lines), into $OUT/scaling.txt; tools/chart-from-renders --scaling charts it here.
# Expects `tools/bundle .bundle` and .bundle/scenes.tar.gz with the shared scenes under scenes/.
. bench/gpu-prelude.sh
for scene in scenes/cornell/scene.cfg scenes/cornell-spheres/scene.cfg scenes/lights-phong/scene.cfg \
    scenes/shared/cornell-original.cfg scenes/shared/teapot.cfg scenes/shared/bunny.cfg \
    scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg; do
    # Brute force over the big scenes would take minutes a frame: only up to the teapot.
    accels="grid bvh"
    case $scene in scenes/shared/bunny.cfg | scenes/shared/s* | scenes/shared/lost*) ;; *) accels="brute grid bvh" ;; esac
    for accel in $accels; do
        for run in 1 2 3; do
            echo "== $scene $accel"
            .bundle/vkrt render "$scene" --width 1920 --height 1080 --spp 1 --accel $accel \
                -o /tmp/scaling.png 2>&1 | grep "ms/frame"
        done
    done
done >"$out/scaling.txt"
grep -c ms/frame "$out/scaling.txt"
