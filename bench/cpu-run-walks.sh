#!/bin/sh
# cpu-run-walks.sh: the BVH's two walks (`vkrt bench --walk one-loop|nested`) on both GPU layouts
# (`--bvh-width 2|4`) on lavapipe, and the probe that found why the nested walk is faster there
# (bench/variants/dead-branch.patch: a branch no lane takes, holding three leaf tests). Run from
# the repository root after `ninja -C build`, beside ../shared (scenes/shared links into it).
# Writes bench/results/lavapipe-walks/: one JSON per layout and walk and round, walks.txt (the
# commands and their output) and dead-branch.txt.
#   bench/cpu-run-walks.sh [WIDTH HEIGHT]      (default 480 270)
set -eu
width=${1:-480}
height=${2:-270}
dir=bench/results/lavapipe-walks
scenes="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
export LP_NUM_THREADS=$(nproc) VKRT_VALIDATION=0
mkdir -p $dir
log=$dir/walks.txt
{
    echo "$(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; vkrt $(git describe --always --dirty);"
    echo "LP_NUM_THREADS=$LP_NUM_THREADS, ${width}x${height}, Mrays/s, median of 11 timed runs"
} >$log
# Two rounds, the four ways in turn in each, so that a change in the machine's load shows as a
# difference between rounds rather than between ways.
for round in 1 2; do
    for way in "2 one-loop" "2 nested" "4 one-loop" "4 nested"; do
        set -- $way
        name=$1-$2-$round
        cmd="build/vkrt bench $scenes --accel bvh --bvh-width $1 --walk $2 --width $width --height $height --json $dir/$name.json"
        echo "\$ $cmd" >>$log
        $cmd >>$log 2>&1
    done
done

# The probe: the one-loop pairs walk on Sponza, as it is and with the never-taken branch.
probe=$(mktemp -d)
trap 'rm -rf "$probe"' EXIT
git archive HEAD glsl | tar x -C "$probe"
(cd "$probe" && patch -s -p1 <"$OLDPWD/bench/variants/dead-branch.patch")
out=$dir/dead-branch.txt
echo "bench/variants/dead-branch.patch on Sponza, the pairs walked in one loop, ${width}x${height}; as is, then with the patch, twice" >$out
for round in 1 2; do
    for glsl in glsl "$probe/glsl"; do
        echo "\$ VKRT_GLSL_DIR=$glsl vkrt bench scenes/shared/sponza.cfg --accel bvh --bvh-width 2 --walk one-loop" >>$out
        VKRT_GLSL_DIR=$glsl build/vkrt bench scenes/shared/sponza.cfg --accel bvh --bvh-width 2 \
            --walk one-loop --width $width --height $height 2>&1 | tail -1 >>$out
    done
done
sed -i "s#$probe/glsl#<glsl with the patch>#" $out
cat $out
