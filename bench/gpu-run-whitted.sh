#!/bin/sh
# gpu-run-whitted.sh: the Whitted Sponza frame (scenes/shared/sponza-whitted.cfg) on the GPU
# machine at 1920x1080 with --profile, five frames of one camera in one process (the first
# pays for the clocks' ramp-up). Expects `tools/bundle .bundle` and .bundle/scenes.tar.gz with
# scenes/dabrovic-sponza (OBJ, MTL, textures). Writes $OUT/whitted.txt and a picture.
. bench/gpu-prelude.sh
nvidia-smi --query-gpu=name,driver_version --format=csv >"$out/whitted.txt" 2>&1
# The same camera five times: one process, so frames 2-5 show the steady state.
cfg=scenes/shared/sponza-whitted-5.cfg
{ grep -v '^output' scenes/shared/sponza-whitted.cfg; grep '^camera' scenes/shared/sponza-whitted.cfg;
  grep '^camera' scenes/shared/sponza-whitted.cfg; grep '^camera' scenes/shared/sponza-whitted.cfg;
  grep '^camera' scenes/shared/sponza-whitted.cfg; } >"$cfg"
.bundle/vkrt render "$cfg" --profile -o "/tmp/whitted%d.png" 2>&1 | grep -v "Both .d." >>"$out/whitted.txt"
cp /tmp/whitted4.png "$out/sponza-whitted.png"
cat "$out/whitted.txt"
