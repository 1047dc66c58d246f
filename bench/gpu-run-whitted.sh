#!/bin/sh
# gpu-run-whitted.sh: the Whitted Sponza frame (scenes/shared/sponza-whitted.cfg) on the GPU
# machine at 1920x1080 with --profile: each frame is rendered once, then again after 300 ms of
# GPU warm-up, 11 times back to back in one submission, and the table shows the median of those
# per dispatch (src/render/renderer.c, run_passes). Two frames of the same camera in one process:
# the second, after the host wrote the first's PNG, should read the same as the first. Expects
# `tools/bundle .bundle` and .bundle/scenes.tar.gz with scenes/dabrovic-sponza (OBJ, MTL,
# textures). Writes $OUT/whitted.txt and a picture.
. bench/gpu-prelude.sh
nvidia-smi --query-gpu=name,driver_version --format=csv >"$out/whitted.txt" 2>&1
cfg=scenes/shared/sponza-whitted-2.cfg
{ grep -v '^output' scenes/shared/sponza-whitted.cfg; grep '^camera' scenes/shared/sponza-whitted.cfg; } >"$cfg"
.bundle/vkrt render "$cfg" --profile-repeat 11 -o "/tmp/whitted%d.png" 2>&1 | grep -v "Both .d." >>"$out/whitted.txt"
cp /tmp/whitted1.png "$out/sponza-whitted.png"
cat "$out/whitted.txt"
