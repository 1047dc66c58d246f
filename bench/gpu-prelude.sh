# gpu-prelude.sh: sourced by the bench/gpu-run-*.sh scripts on the GPU machine. Sets $out (the
# folder whose files come back, $OUT) and $root, unpacks .bundle/scenes.tar.gz and links it
# where the scene files expect ../shared/scenes. The caller unpacks .gl/*.deb first: libvulkan1,
# and since the fourth pass of issue 8 libegl1 and libglvnd0 too (Debian's; the machine's NVIDIA
# driver 580 would not create an instance without glvnd's libEGL).
set -u
out=${OUT:-/tmp/vkrt-out}
mkdir -p "$out"
root=$(pwd)
(cd .bundle && tar xzf scenes.tar.gz)
mkdir -p ../shared && ln -sfn "$root/.bundle/scenes" ../shared/scenes

# For the scripts from gpu-run-pass3.sh on (the earlier ones keep the copies they ran with):
# run NAME WIDTH HEIGHT COMMAND...: one bench run at that size, its JSON as $json/NAME.json and
# its table appended to $log. gpu_tests NAME...: the bundle's tests/test_NAME, each exit status
# and the end of its output into $log (unpacks .bundle/tests.tar.xz once).
run() {
    name=$1 w=$2 h=$3; shift 3
    echo "== $name ${w}x$h: $*" >>"$log"
    "$@" --width "$w" --height "$h" --json "$json/$name.json" 2>&1 | grep -v "Both .d." | tee -a "$log"
}
gpu_tests() {
    [ -f .bundle/tests.tar.xz ] && [ ! -x .bundle/bin/test_accel ] && tar xJf .bundle/tests.tar.xz -C .bundle/bin
    for t in "$@"; do
        [ -x .bundle/bin/test_$t ] || continue
        timeout 300 .bundle/bin/test_$t >/tmp/test_$t.txt 2>&1
        status=$?
        { echo "== test_$t exit $status${VKRT_GLSL_DIR:+ (kernels of $VKRT_GLSL_DIR)}"; tail -3 /tmp/test_$t.txt; } >>"$log"
        echo "test_$t exit $status"
    done
}

# For the scripts from gpu-run-walks.sh on: begin NAME sets the bundle's environment, $log
# ($out/NAME-log.txt, opened with the GPU's name, driver and clocks) and $json (a folder for the
# runs' JSON); end NAME packs $json into $out/NAME-json.tar and appends the clocks, temperature
# and power after the runs to $log.
begin() {
    export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0 VKRT_SOURCE_DIR="$root" \
        VKRT_SCENES_DIR="$root/.bundle/scenes" VKRT_STADIUM_CFG="$root/.bundle/stadium/scene.cfg"
    log="$out/$1-log.txt"
    json=/tmp/$1-json
    mkdir -p "$json"
    nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$log" 2>&1
}
end() {
    tar cf "$out/$1-json.tar" -C "$json" .
    nvidia-smi --query-gpu=clocks.sm,temperature.gpu,power.draw --format=csv >>"$log" 2>&1
}
