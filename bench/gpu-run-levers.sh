#!/bin/sh
# gpu-run-levers.sh: the second pass at issue 8's misses, on the GPU machine in one call:
#   1. vkrt bench of the four issue-8 scenes at 1920x1080, the baseline (its build_ms is the new
#      BVH build on this host's cores);
#   2. diffuse rays ordered by direction cell on the host (--sort-diffuse 2, 4, 8, 16), timed,
#      and counted with --stats;
#   3. the traversal stack's first 32 entries in shared memory: the kernel variant in
#      .bundle/variants/shared-stack (VKRT_GLSL_DIR), with workgroups of 64 and 128;
#   4. the fixed cost of a dispatch: bunny and the Cornell box at 320x180 to 3840x2160;
#   5. the baseline again, for drift.
# Expects .bundle from tools/bundle with scenes.tar.gz (bench/gpu-prelude.sh) and the variant,
# the kernels with bench/variants/shared-stack.patch applied, made by:
#   mkdir -p /tmp/v .bundle/variants && cp -r glsl /tmp/v/ &&
#   patch -p1 -d /tmp/v <bench/variants/shared-stack.patch && cp -r /tmp/v/glsl .bundle/variants/shared-stack
# Writes $OUT/levers-log.txt and $OUT/levers-json.tar.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0
log="$out/levers-log.txt"
json=/tmp/levers-json
mkdir -p $json
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$log" 2>&1
nproc >>"$log"
issue="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
run() { # name, width, height, command...: one run, its table into the log
    name=$1 w=$2 h=$3; shift 3
    echo "== $name ${w}x$h: $*" >>"$log"
    "$@" --width "$w" --height "$h" --json "$json/$name.json" 2>&1 | grep -v "Both .d." | tee -a "$log"
}
run base 1920 1080 .bundle/vkrt bench $issue --accel bvh
for cells in 2 4 8 16; do
    run sort$cells 1920 1080 .bundle/vkrt bench $issue --accel bvh --sort-diffuse $cells
done
run stats 1920 1080 .bundle/vkrt bench $issue --accel bvh --stats
run stats-sort4 1920 1080 .bundle/vkrt bench $issue --accel bvh --stats --sort-diffuse 4
run stats-sort16 1920 1080 .bundle/vkrt bench $issue --accel bvh --stats --sort-diffuse 16
for wg in 64 128; do
    VKRT_GLSL_DIR="$root/.bundle/variants/shared-stack" \
        run shared-wg$wg 1920 1080 .bundle/vkrt bench $issue --accel bvh --workgroup $wg
done
for size in 320x180 960x540 1920x1080 2560x1440 3840x2160; do
    run size-$size "${size%x*}" "${size#*x}" .bundle/vkrt bench scenes/shared/bunny.cfg \
        scenes/cornell/scene.cfg --accel bvh
done
run base-again 1920 1080 .bundle/vkrt bench $issue --accel bvh
tar cf "$out/levers-json.tar" -C $json .
nvidia-smi --query-gpu=clocks.sm,temperature.gpu,power.draw --format=csv >>"$log" 2>&1
