#!/bin/sh
# gpu-run-chart.sh: the renders of tools/chart's error-against-time ladder for the Cornell box
# with mirror and glass spheres, on the GPU machine (which has no Python packages): every
# accel x max-depth x spp at 128x128 as EXR, the summary line of each, and a converged reference
# (BVH, 4096 spp, max-depth 8). tools/chart-from-renders turns them into the chart here.
# Expects `tools/bundle .bundle`. Writes $OUT/chart-renders.tar.gz.
set -u
out=${OUT:-/tmp/vkrt-out}
work=/tmp/chart
mkdir -p "$out" "$work"
size="--width 128 --height 128"
for depth in 1 2 8; do
    { grep -v '^max-depth' scenes/cornell-spheres/scene.cfg |
          sed "s|^geometry *|geometry $(pwd)/scenes/cornell-spheres/|"; echo "max-depth $depth"; } \
        >"$work/depth$depth.cfg"
done
.bundle/vkrt render "$work/depth8.cfg" $size --spp 4096 --accel bvh -o "$work/reference.exr" \
    2>"$work/reference.txt"
for depth in 1 2 8; do
    for accel in brute grid bvh; do
        for spp in 1 4 16 64; do
            name="$accel-d$depth-s$spp"
            # The fastest of three runs, as tools/chart takes it (the first pays for compiling).
            for run in 1 2 3; do
                .bundle/vkrt render "$work/depth$depth.cfg" $size --spp $spp --accel $accel \
                    -o "$work/$name.exr" 2>>"$work/$name.txt"
            done
        done
    done
done
(cd "$work" && tar czf "$out/chart-renders.tar.gz" ./*.exr ./*.txt)
ls "$work" | wc -l
