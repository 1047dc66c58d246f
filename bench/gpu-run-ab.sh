#!/bin/sh
# gpu-run-ab.sh: one kernel change against the build before it, on the GPU machine: vkrt bench of
# the four issue-8 scenes at 1920x1080 by .bundle (the change) and .bundle-old/bin/vkrt (the
# build before it, with .bundle's libraries), twice each, interleaved; then --stats of the change.
# Writes $OUT/ab-log.txt and $OUT/ab-json.tar.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib"
scenes="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
log="$out/ab-log.txt"
json=/tmp/ab-json
mkdir -p $json
for run in 1 2; do
    for which in new old; do
        bin=.bundle/bin/vkrt
        [ $which = old ] && bin=.bundle-old/bin/vkrt
        echo "== $which $run" >>"$log"
        $bin bench $scenes --accel bvh --width 1920 --height 1080 --json "$json/$which-$run.json" 2>&1 |
            grep -v "Both .d." | tee -a "$log"
    done
done
.bundle/bin/vkrt bench $scenes --accel bvh --width 1920 --height 1080 --stats --json "$json/stats.json" 2>&1 | tee -a "$log"
tar cf "$out/ab-json.tar" -C $json .
