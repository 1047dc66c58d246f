#!/bin/sh
# gpu-run-kernel.sh: the traversal kernel on the GPU machine, old against new, in one call:
#   1. the GPU tests (correctness of the kernel on this driver; no validation layers there);
#   2. vkrt bench of the four issue-8 scenes at 1920x1080 with the BVH, by this build (.bundle)
#      and, when .bundle-old exists, by the build before the change (same rays, same machine);
#   3. vkrt bench --stats (records fetched, triangles tested, SIMD utilisation per ray kind);
#   4. static ray fetch (--ray-fetch static), the driver's pipeline (rtpipe-bench) when bundled, a workgroup-size sweep when SWEEP is set, and the same
#      bench with the whole scene (materials, textures) loaded.
# Expects `tools/bundle .bundle build/tests/test_...` (see the loop below), optionally
# .bundle-old made the same way from the older commit, and .bundle/scenes.tar.gz (the shared
# scenes under scenes/, the teapot stadium under stadium/). Writes $OUT/kernel-log.txt and
# $OUT/kernel-json.tar (the JSON of every bench run: only 8 files come back from a call).
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0 VKRT_SOURCE_DIR="$root" \
    VKRT_SCENES_DIR="$root/.bundle/scenes" VKRT_STADIUM_CFG="$root/.bundle/stadium/scene.cfg"
scenes="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
log="$out/kernel-log.txt"
mkdir -p /tmp/kjson
{ nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv; } >"$log" 2>&1
for t in layout render accel stability materials; do
    [ -x .bundle/bin/test_$t ] || continue
    timeout 300 .bundle/bin/test_$t >/tmp/test_$t.txt 2>&1
    status=$?
    { echo "== test_$t exit $status"; tail -4 /tmp/test_$t.txt; } >>"$log"
    echo "test_$t exit $status"
done
bench() { # name, extra arguments: one bench run of the four scenes
    name=$1; shift
    accel="--accel bvh"; case $1 in *rtpipe-bench) accel="" ;; esac
    echo "== $name: vkrt bench $*" >>"$log"
    "$@" $scenes $accel --width 1920 --height 1080 --json "/tmp/kjson/kernel-$name.json" 2>&1 |
        grep -v "Both .d." | tee -a "$log"
}
bench new .bundle/vkrt bench
bench static .bundle/vkrt bench --ray-fetch static
[ -x .bundle-old/bin/vkrt ] && bench old .bundle-old/bin/vkrt bench
bench stats .bundle/vkrt bench --stats
bench stats-static .bundle/vkrt bench --stats --ray-fetch static
[ -n "${SWEEP:-}" ] && for wg in 32 128 256; do bench wg$wg .bundle/vkrt bench --workgroup $wg; done
bench whole .bundle/vkrt bench --whole-scene
[ -x .bundle/rtpipe-bench ] && bench rtpipe .bundle/rtpipe-bench
bench new-again .bundle/vkrt bench
nvidia-smi --query-gpu=clocks.sm,temperature.gpu,power.draw --format=csv >>"$log" 2>&1
tar cf "$out/kernel-json.tar" -C /tmp/kjson .
