#!/bin/sh
# The lavapipe measurements of issue 35's start-up case (log.txt), run from the repository root:
#   research/results/lavapipe-gltf-startup/run.sh > research/results/lavapipe-gltf-startup/log.txt 2>&1
# Scenes: tools/textured_gltf.py /tmp/wt2-ext and tools/textured_gltf.py /tmp/wt2-glb --embed.
# Each: cold (VKRT_CACHE_DIR emptied), warm, and warm with VKRT_TEXTURE_THREADS=1 (textures decoded
# one at a time, as before decoding ahead) and =2 (both cores), 160 x 90, 1 spp, --verbose.
for v in ext/textured.gltf glb/textured.glb; do
    cache=/tmp/wt2-results-cache-${v%%/*}
    rm -rf "$cache"
    for pass in cold warm serial parallel serial parallel; do
        threads=""
        [ $pass = serial ] && threads=1
        [ $pass = parallel ] && threads=2
        echo "== $v $pass${threads:+ VKRT_TEXTURE_THREADS=$threads}; load average $(cut -d' ' -f1-3 /proc/loadavg)"
        VKRT_TEXTURE_THREADS=$threads VKRT_CACHE_DIR=$cache /usr/bin/time -f "wall %e s, user %U s, sys %S s" \
            build/vkrt render /tmp/wt2-$v --width 160 --height 90 --spp 1 --verbose \
            -o /tmp/wt2-results-$pass.png 2>&1 | grep -E "start-up|scene cache|wall|error"
    done
    cmp /tmp/wt2-results-serial.png /tmp/wt2-results-parallel.png && echo "== serial and parallel pictures identical"
done
