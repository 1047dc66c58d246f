#!/bin/sh
# gpu-run-rays.sh: primary, shadow and diffuse bounce rays per scene on the GPU machine (an H100),
# 1920x1080, BVH. Expects `tools/bundle .bundle` and .bundle/scenes.tar.gz with the shared scenes
# (OBJ, MTL and textures: scenes load whole) under scenes/. Writes $OUT/rays-h100.json and .txt.
. bench/gpu-prelude.sh
.bundle/vkrt bench scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg \
    scenes/shared/lost-empire.cfg --accel bvh --width 1920 --height 1080 \
    --json "$out/rays-h100.json" 2>&1 | grep -v "Both .d." | tee "$out/rays-h100.txt"
