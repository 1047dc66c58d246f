#!/bin/sh
# cpu-run-pass6.sh: the sixth pass's lavapipe record. This session's dev machine (AMD EPYC with
# AVX-512, 2 cores) ran lavapipe at under half the rates the fifth pass's did with the same
# Debian packages and kernels, while Embree lost far less. This measures, in two rounds, Embree 3
# (build/embree-bench, 2 threads) and vkrt bench (accel bvh, the CPU defaults) with llvmpipe's
# vectors at the width it picks (256 bits, subgroups of 8), at 512 bits (LP_NATIVE_VECTOR_WIDTH,
# subgroups of 16) and at 128 bits (GALLIUM_OVERRIDE_CPU_CAPS=sse4.1, which also turns off AVX:
# subgroups of 4), on issue 8's four scenes at 480x270. Run from the repository root after
# `ninja -C build` on a machine with libembree-dev. Writes bench/results/lavapipe-pass6/.
set -eu
results=bench/results/lavapipe-pass6
scenes="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
export LP_NUM_THREADS=$(nproc) VKRT_VALIDATION=0
[ -x build/embree-bench ] || { echo "build/embree-bench is missing: install libembree-dev, then ninja -C build" >&2; exit 1; }
mkdir -p "$results"
log="$results/log.txt"
{
    lscpu | grep -E "Model name|^CPU\(s\)"
    echo "avx512 flags: $(grep -o 'avx512[a-z_]*' /proc/cpuinfo | sort -u | tr '\n' ' ')"
    dpkg-query -W -f '${Package} ${Version}\n' mesa-vulkan-drivers libembree3-3 2>/dev/null || true
    echo "LP_NUM_THREADS=$LP_NUM_THREADS, 480x270, Mrays/s, median of 11 timed runs"
} >"$log"
for round in 1 2; do
    echo "== embree-$round" >>"$log"
    build/embree-bench $scenes --width 480 --height 270 --threads "$LP_NUM_THREADS" \
        --json "$results/embree-$round.json" 2>&1 | tee -a "$log"
    for width in 256 512 128; do
        echo "== vkrt-$width-$round" >>"$log"
        if [ "$width" = 128 ]; then
            set -- env GALLIUM_OVERRIDE_CPU_CAPS=sse4.1
        else
            set -- env LP_NATIVE_VECTOR_WIDTH=$width
        fi
        "$@" build/vkrt bench $scenes --accel bvh --width 480 --height 270 \
            --json "$results/vkrt-$width-$round.json" 2>&1 | tee -a "$log"
    done
done
