#!/bin/sh
# gpu-run-flight.sh: the Sponza flythrough recorded in `vkrt view` (scenes/shared/sponza-flight.cfg,
# 25 cameras; scenes/shared/sponza-flight.events flew it) rendered by `vkrt render` on the GPU
# machine, an H100 without a display, at the scene's 1920x1080 and 16 spp; and `vkrt view`
# there, which must say it needs a display. Expects a bundle (tools/bundle's layout) in $BUNDLE
# (default .bundle) with scenes.tar.gz holding scenes/dabrovic-sponza, and the Vulkan loader
# (unpack .gl/*.deb first where the machine has none). Writes $OUT/flight.txt and frames 0, 6,
# 12, 18 and 24.
set -u
out=${OUT:-/tmp/vkrt-out}
bundle=${BUNDLE:-.bundle}
mkdir -p "$out" /tmp/flight
root=$(pwd)
(cd "$bundle" && tar xzf scenes.tar.gz)
mkdir -p ../shared && ln -sfn "$root/$bundle/scenes" ../shared/scenes
{
    nvidia-smi --query-gpu=name,driver_version --format=csv
    echo "DISPLAY=${DISPLAY:-unset}"
    "$bundle/vkrt" view scenes/shared/sponza-flight.cfg
    echo "view exit $?"
    "$bundle/vkrt" render scenes/shared/sponza-flight.cfg --spp 16 -o /tmp/flight/f%02d.png
    echo "render exit $?"
    echo "$(ls /tmp/flight | wc -l) frames written"
} 2>&1 | grep -v "Both .d." | tee "$out/flight.txt"
for f in 00 06 12 18 24; do cp "/tmp/flight/f$f.png" "$out/"; done
