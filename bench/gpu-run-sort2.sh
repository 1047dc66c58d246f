#!/bin/sh
# gpu-run-sort2.sh: the ray sort after its first measurement (bench/gpu-run-sort.sh), on the GPU
# machine: test_ray_sort, then vkrt bench of the four issue-8 scenes at 1920x1080 without the
# sort and with it (--sort-diffuse 4 and 8, twice each, interleaved). Expects .bundle from
# `tools/bundle .bundle build/tests/test_ray_sort` with the test in .bundle/tests.tar.xz, and
# .bundle/scenes.tar.gz. Writes $OUT/sort2-log.txt and $OUT/sort2-json.tar.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0
log="$out/sort2-log.txt"
json=/tmp/sort2-json
mkdir -p $json
[ -f .bundle/tests.tar.xz ] && tar xJf .bundle/tests.tar.xz -C .bundle/bin
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$log" 2>&1
timeout 300 .bundle/bin/test_ray_sort >/tmp/test_ray_sort.txt 2>&1
echo "== test_ray_sort exit $?" >>"$log"
grep -E "cells|OK|FAIL" /tmp/test_ray_sort.txt >>"$log"
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
run() { # name, command...: one run, its table into the log
    name=$1; shift
    echo "== $name: $*" >>"$log"
    "$@" --width 1920 --height 1080 --json "$json/$name.json" 2>&1 | grep -v "Both .d." | tee -a "$log"
}
for round in 1 2; do
    run base-$round .bundle/vkrt bench $issue --accel bvh
    run sort4-$round .bundle/vkrt bench $issue --accel bvh --sort-diffuse 4
    run sort8-$round .bundle/vkrt bench $issue --accel bvh --sort-diffuse 8
done
tar cf "$out/sort2-json.tar" -C $json .
