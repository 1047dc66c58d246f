#!/bin/sh
# cpu-run-mesa25.sh: whether a newer llvmpipe closes lavapipe's gap to Embree (issue 8; see
# bench/cpu-run-embree.sh). Runs vkrt bench on the issue's scenes at 480x270 with Debian 12's
# lavapipe (Mesa 22.3) and with Mesa 25.0 from Debian's bookworm-backports, each with the CPU
# default (4-wide nodes, nested walk) and the GPU default (pairs, one loop), in turn, twice.
# Nothing is installed: mesa-vulkan-drivers and the libdrm it needs are downloaded from the
# backports suite of the machine's own Debian mirror (the first URIs of
# /etc/apt/sources.list.d/debian.sources) and unpacked into .mesa25/ (ignored by git); the Vulkan
# loader is pointed at its ICD (VK_DRIVER_FILES) and the dynamic linker at its libraries. Run from
# the repository root after `ninja -C build`, beside ../shared. Writes bench/results/lavapipe-mesa25/:
# runs.txt (the commands and their output) and a JSON per Mesa, layout and round.
set -eu
dir=$PWD/.mesa25
lib=$dir/root/usr/lib/x86_64-linux-gnu
if [ ! -f "$dir/lvp_icd.json" ]; then
    mirror=$(awk '/^URIs:/ { print $2; exit }' /etc/apt/sources.list.d/debian.sources)
    mkdir -p "$dir/lists/partial" "$dir/debs" "$dir/root"
    echo "deb $mirror bookworm-backports main" >"$dir/sources.list"
    o="-o Dir::Etc::SourceList=$dir/sources.list -o Dir::Etc::SourceParts=/dev/null -o Dir::State::Lists=$dir/lists"
    # shellcheck disable=SC2086 # the options are meant to split into words
    apt-get $o update -q
    # shellcheck disable=SC2086
    (cd "$dir/debs" && apt-get $o download mesa-vulkan-drivers/bookworm-backports \
        libdrm2/bookworm-backports libdrm-amdgpu1/bookworm-backports)
    for f in "$dir"/debs/*.deb; do dpkg -x "$f" "$dir/root"; done
    sed "s#\"libvulkan_lvp.so\"#\"$lib/libvulkan_lvp.so\"#" \
        "$dir/root/usr/share/vulkan/icd.d/lvp_icd.json" >"$dir/lvp_icd.json"
fi
out=bench/results/lavapipe-mesa25
mkdir -p $out
log=$out/runs.txt
scenes="scenes/shared/bunny.cfg scenes/shared/sponza.cfg scenes/shared/sibenik.cfg scenes/shared/lost-empire.cfg"
export LP_NUM_THREADS=$(nproc) VKRT_VALIDATION=0
{
    echo "$(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; vkrt $(git describe --always --dirty);"
    backport=$(ls "$dir/debs" | sed -n 's/^mesa-vulkan-drivers_\(.*\)_amd64.deb$/\1/p')
    echo "Mesa 22.3: $(dpkg-query -W -f '${Version}' mesa-vulkan-drivers); Mesa 25.0: $backport"
    echo "LP_NUM_THREADS=$LP_NUM_THREADS, 480x270, Mrays/s, median of 11 timed runs"
} >$log
for round in 1 2; do
    for mesa in 22 25; do
        for way in "4 nested" "2 one-loop"; do
            set -- $way
            name=mesa$mesa-$1-$2-$round
            cmd="build/vkrt bench $scenes --accel bvh --bvh-width $1 --walk $2 --width 480"
            cmd="$cmd --height 270 --json $out/$name.json"
            echo "\$ $([ $mesa = 25 ] && echo 'VK_DRIVER_FILES=.mesa25/lvp_icd.json ')$cmd" >>$log
            if [ $mesa = 25 ]; then
                VK_DRIVER_FILES=$dir/lvp_icd.json LD_LIBRARY_PATH=$lib $cmd >>$log 2>&1
            else
                $cmd >>$log 2>&1
            fi
        done
    done
done
cat $log
