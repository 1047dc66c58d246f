#!/bin/sh
# cpu-run-variant.sh: a kernel variant (a patch of glsl/ from bench/variants/) against the
# committed kernels on lavapipe, run in turn so that the machine's drift shows in both. Run from
# the repository root after `ninja -C build`, beside ../shared (scenes/shared links into it).
#   bench/cpu-run-variant.sh PATCH [ROUNDS [SCENE...]]   (default 6 rounds of sponza and bunny)
# Each run is `vkrt bench` at 480x270 with the CPU device's defaults, through VKRT_GLSL_DIR.
# Writes bench/results/lavapipe-variants/NAME.txt (NAME: the patch's, without .patch): every
# run's line, then per scene and kernels the median and range of each ray kind's Mrays/s. A
# variant that finds other hits or blocked rays than the committed kernels is an error.
set -eu
patch_file=$1
rounds=${2:-6}
shift $(( $# < 2 ? $# : 2 ))
scenes=${*:-sponza bunny}
name=$(basename "$patch_file" .patch)
dir=bench/results/lavapipe-variants
out=$dir/$name.txt
export LP_NUM_THREADS=$(nproc) VKRT_VALIDATION=0
mkdir -p $dir
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Both sides from the last commit, so that uncommitted changes of glsl/ are on neither.
mkdir -p "$work/committed" "$work/variant"
git archive HEAD glsl | tar x -C "$work/committed"
git archive HEAD glsl | tar x -C "$work/variant"
patch_path=$(cd "$(dirname "$patch_file")" && pwd)/$(basename "$patch_file")
(cd "$work/variant" && patch -s -p1 --batch --forward <"$patch_path")
{
    echo "$(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; vkrt $(git describe --always --dirty);"
    echo "LP_NUM_THREADS=$LP_NUM_THREADS, 480x270, $rounds rounds;" \
        "the committed kernels (glsl/ at HEAD) and $patch_file in turn"
    echo "round scene kernels primary shadow diffuse hits blocked (Mrays/s, vkrt bench's median of 11 timed runs)"
} >$out
for round in $(seq "$rounds"); do
    for s in $scenes; do
        for kernels in committed variant; do
            label=$([ $kernels = committed ] && echo committed || echo "$name")
            VKRT_GLSL_DIR=$work/$kernels/glsl build/vkrt bench "scenes/shared/$s.cfg" --accel bvh \
                --width 480 --height 270 2>&1 | tail -1 |
                awk -v r="$round" -v s="$s" -v k="$label" '{ print r, s, k, $6, $7, $8, $9, $10 }' >>$out
        done
    done
done
python3 - "$out" <<'EOF'
import collections, statistics, sys
path = sys.argv[1]
runs = collections.defaultdict(list)
counts = collections.defaultdict(set)
for line in open(path).readlines()[3:]:
    r, scene, kernels, *rates, hits, blocked = line.split()
    runs[scene, kernels].append([float(x) for x in rates])
    counts[scene].add((hits, blocked))
lines = ["", "median (min-max) Mrays/s over the rounds: primary / shadow / diffuse"]
for (scene, kernels), xs in runs.items():
    cells = []
    for i in range(3):
        v = [x[i] for x in xs]
        cells.append("%.2f (%.2f-%.2f)" % (statistics.median(v), min(v), max(v)))
    lines.append("%-12s %-14s %s" % (scene, kernels, " / ".join(cells)))
bad = [s for s, c in counts.items() if len(c) != 1]
if bad:
    lines.append("hits or blocked rays differ between the kernels on " + ", ".join(bad))
open(path, "a").write("\n".join(lines) + "\n")
print("\n".join(lines))
sys.exit(1 if bad else 0)
EOF
