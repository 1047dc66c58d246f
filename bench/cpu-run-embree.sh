#!/bin/sh
# cpu-run-embree.sh: vkrt on lavapipe against Embree 3 on the same CPU, scenes and rays (issue 8:
# at least half Embree's primary-ray throughput). Run from the repository root after
# `ninja -C build` on a machine with libembree-dev, so that build/embree-bench exists. Writes
#   bench/results/embree-lavapipe.txt, .json           embree-bench's output
#   bench/results/vkrt-lavapipe-vs-embree.txt, .json   vkrt bench --accel auto and bvh beside it
# and then docs/performance.md (tools/performance_doc.py).
#   bench/cpu-run-embree.sh [WIDTH HEIGHT]      (default 480 270: lavapipe takes about a minute a scene)
# Both tracers get every core: lavapipe runs a compute dispatch on LP_NUM_THREADS threads,
# embree-bench on --threads. A scene's three runs go back to back, after waiting (up to
# QUIET_WAIT seconds, default 120) for other processes to leave the CPU, since on a shared machine
# they would slow whichever tracer ran beside them; the share of CPU they took while the scene ran
# is recorded with the results.
set -eu
width=${1:-480}
height=${2:-270}
scenes="bunny sponza sibenik lost-empire"
threads=$(nproc)
export LP_NUM_THREADS=$threads VKRT_VALIDATION=0
results=bench/results
[ -x build/embree-bench ] || { echo "build/embree-bench is missing: install libembree-dev, then ninja -C build" >&2; exit 1; }
run=$(mktemp -d)
trap 'rm -rf "$run"' EXIT

# Busy and total jiffies of all CPUs so far (/proc/stat's first line).
cpu_jiffies() {
    awk '/^cpu /{ print $2 + $3 + $4 + $7 + $8, $2 + $3 + $4 + $5 + $6 + $7 + $8 }' /proc/stat
}

# CPU time of this shell's finished children, the benchmarks (/proc/PID/stat's cutime + cstime).
children_jiffies() {
    awk '{ print $16 + $17 }' /proc/$$/stat
}

# Waits until the CPU is less than 10% busy over a second, or QUIET_WAIT seconds have passed.
wait_quiet() {
    waited=0
    while [ "$waited" -lt "${QUIET_WAIT:-120}" ]; do
        set -- $(cpu_jiffies); b0=$1 t0=$2
        sleep 1
        set -- $(cpu_jiffies)
        [ $(( ($1 - b0) * 10 )) -lt $(( $2 - t0 )) ] && return 0
        waited=$((waited + 1))
    done
    echo "cpu-run-embree: the CPU is still busy after ${QUIET_WAIT:-120} s; measuring anyway" >&2
}

# The output of one benchmark command, its three header lines only for the first scene.
keep() {
    if [ "$1" = first ]; then cat; else tail -n +4; fi
}

: >"$run/embree.txt"
: >"$run/vkrt.txt"
first=first
for s in $scenes; do
    cfg=scenes/shared/$s.cfg
    [ -f "$cfg" ] || { echo "$cfg is missing" >&2; exit 1; }
    echo "$s" >>"$run/scenes"
    wait_quiet
    set -- $(cpu_jiffies); busy0=$1 total0=$2 ours0=$(children_jiffies)
    build/embree-bench "$cfg" --width "$width" --height "$height" --threads "$threads" \
        --json "$run/embree-$s.json" | keep $first | tee -a "$run/embree.txt"
    [ -f "$run/embree-$s.json" ] || { echo "embree-bench failed on $cfg" >&2; exit 1; }
    for accel in auto bvh; do
        build/vkrt bench "$cfg" --accel $accel --width "$width" --height "$height" \
            --json "$run/$accel-$s.json" | keep $first | tee -a "$run/vkrt.txt"
        [ -f "$run/$accel-$s.json" ] || { echo "vkrt bench failed on $cfg" >&2; exit 1; }
        first=later
    done
    # What others took: all CPUs' busy time less this shell's children (the benchmarks).
    set -- $(cpu_jiffies)
    echo "$busy0 $total0 $1 $2 $(( $(children_jiffies) - ours0 ))" |
        awk '{ o = $3 - $1 - $5; printf "%.3f\n", (o < 0 ? 0 : o) / ($4 - $2) }' >"$run/busy-$s.txt"
done
cp "$run/embree.txt" "$results/embree-lavapipe.txt"
python3 tools/embree_compare.py merge "$run" "$results"
{ echo; echo "vkrt bench's own output:"; cat "$run/vkrt.txt"; } >>"$results/vkrt-lavapipe-vs-embree.txt"
python3 tools/performance_doc.py
