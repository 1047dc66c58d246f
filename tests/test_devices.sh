#!/bin/sh
# test_devices.sh: `vkrt render --devices` (src/device_pool.h): a flythrough spread over worker
# processes writes the same bytes as one device does, a worker killed with SIGKILL mid-run loses
# no frame, and the option's bad uses are refused. lavapipe has one device: `--devices 0,0` gives
# it two workers, which is what the queue and the failure handling need. Run by meson test with
# VKRT_BINARY and VKRT_SOURCE_DIR set.
set -u
vkrt=${VKRT_BINARY:?}
src=${VKRT_SOURCE_DIR:?}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$src/tests/lib.sh"

# fly FILE FRAMES SIZE: a flythrough of the Cornell box, FRAMES cameras sliding sideways, with
# motion blur (each frame reads the next frame's camera) under the path tracer's sampler.
fly() {
    {
        echo "geometry $src/scenes/cornell/cornell.obj"
        echo "resolution $3 $3"
        echo "samples 2"
        echo "integrator path"
        echo "shutter 0.5"
        echo "light point 278 500 279 250000 250000 250000"
        i=0
        while [ $i -lt "$2" ]; do
            echo "camera eye $((200 + 7 * i)) 273 -800 look 278 273 0 up 0 1 0 fov 40"
            i=$((i + 1))
        done
    } >"$1"
}

# same_frames PREFIX REFERENCE COUNT: every frame PREFIXnn.png exists and has REFERENCEnn.png's bytes.
same_frames() {
    i=0
    while [ $i -lt "$3" ]; do
        n=$(printf %02d $i)
        cmp -s "$1$n.png" "$2$n.png" || { echo "frame $n differs or is missing ($1$n.png)"; return 1; }
        i=$((i + 1))
    done
}

# The frames the summary's per-device lines of file $1 add up to.
frames_sum() {
    sed -n 's/^vkrt: device [0-9]* (.*): \([0-9]*\) frames\{0,1\}, .*/\1/p' "$1" | awk '{ s += $1 } END { print s + 0 }'
}

# The children of process $1, read from /proc (procps may not be installed).
children() {
    for stat in /proc/[0-9]*/stat; do
        read -r child _ _ parent _ <"$stat" 2>/dev/null && [ "$parent" = "$1" ] && echo "$child"
    done
}

frames=16
fly "$tmp/fly.cfg" $frames 32
# The reference: one device, each file written on the render thread before the next frame.
VKRT_WRITE_THREADS=0 "$vkrt" render "$tmp/fly.cfg" --quiet -o "$tmp/one%02d.png"
check "the single-device reference renders" test $? -eq 0
# Written by 3 threads while the next frames render (src/output/write_pool.h): the same bytes.
VKRT_WRITE_THREADS=3 "$vkrt" render "$tmp/fly.cfg" -o "$tmp/threads%02d.png" 2>"$tmp/err"
check "frames written by 3 threads have the bytes of frames written one at a time" \
    same_frames "$tmp/threads" "$tmp/one" $frames
check "whose progress line counts every frame" grep -q "^vkrt: $frames of $frames frames done" "$tmp/err"

# Two workers on the one device: the frames are shared out, and each is the single run's bytes.
"$vkrt" render "$tmp/fly.cfg" --devices 0,0 -o "$tmp/two%02d.png" 2>"$tmp/err"
check "--devices 0,0 exits 0" test $? -eq 0
check "--devices 0,0 writes every frame with the single device's bytes" same_frames "$tmp/two" "$tmp/one" $frames
check "a summary line per worker" test "$(grep -c '^vkrt: device 0 (.*): [0-9]* frames\{0,1\}, [0-9.]* ms/frame$' "$tmp/err")" -eq 2
check "whose frames add up to the flythrough" \
    test "$(frames_sum "$tmp/err")" -eq $frames
check "and the progress line counts to the end" grep -q "^vkrt: $frames of $frames frames done" "$tmp/err"
check "no temporaries are left" sh -c "! ls '$tmp' | grep -q 'tmp-'"

# Ctrl-C (SIGINT to the parent; stopped around it so that frames are left): the frames being
# rendered finish, exit 130, and --resume with --devices renders just the rest.
"$vkrt" render "$tmp/fly.cfg" --devices 0,0 -o "$tmp/int%02d.png" 2>"$tmp/err" &
pid=$!
waited=0
while [ ! -e "$tmp/int00.png" ] && [ $waited -lt 600 ]; do sleep 0.05; waited=$((waited + 1)); done
kill -STOP $pid
kill -INT $pid
kill -CONT $pid
wait $pid
check "an interrupted --devices run exits 130" test $? -eq 130
check "and says how to continue" grep -q "^vkrt: interrupted after [0-9]* of $frames frames; run again with --resume" "$tmp/err"
written=$(find "$tmp" -name 'int*.png' | wc -l)
check "some but not all frames were written" test "$written" -gt 0 -a "$written" -lt $frames
"$vkrt" render "$tmp/fly.cfg" --devices 0,0 --resume -o "$tmp/int%02d.png" 2>"$tmp/err"
check "--devices with --resume exits 0" test $? -eq 0
check "and renders just the missing frames" grep -q "^vkrt: resumed: $written of $frames frames were already complete" "$tmp/err"
check "with the single device's bytes" same_frames "$tmp/int" "$tmp/one" $frames

# A worker killed mid-run (kill -9: no chance to clean up): its frame goes to the others, every
# frame is written once, the run succeeds and names the worker that failed. The parent is stopped
# (SIGSTOP) around the kill so that frames are left to hand out however fast the frames go;
# tests/test_device_pool.c kills a worker holding a frame for certain.
"$vkrt" render "$tmp/fly.cfg" --devices 0,0,0 -o "$tmp/kill%02d.png" 2>"$tmp/err" &
pid=$!
waited=0
while [ ! -e "$tmp/kill00.png" ] && [ $waited -lt 600 ]; do sleep 0.05; waited=$((waited + 1)); done
kill -STOP $pid
victim=$(children $pid | head -n 1)
check "the run has worker processes" test -n "$victim"
[ -n "$victim" ] && kill -9 "$victim"
kill -CONT $pid
wait $pid
status=$?
check "a run that lost a worker exits 0" test $status -eq 0
check "every frame is there with the single device's bytes" same_frames "$tmp/kill" "$tmp/one" $frames
check "the lost worker is reported" grep -q '^vkrt: device 0 (.*) failed after [0-9]* frames\{0,1\}: killed by signal 9' "$tmp/err"
check "the others' frames add up to the flythrough" test "$(frames_sum "$tmp/err")" -eq $frames
check "no temporaries are left" sh -c "! ls '$tmp' | grep -q 'tmp-'"
[ $status -eq 0 ] || cat "$tmp/err"

# A file that cannot be written (frame 3's folder is a file) fails the worker that renders it,
# then the other; the run names the file, exits 1 and leaves no temporary.
mkdir "$tmp/d"
i=0
while [ $i -lt $frames ]; do mkdir "$tmp/d/$i"; i=$((i + 1)); done
rmdir "$tmp/d/3" && : >"$tmp/d/3"
VKRT_WRITE_THREADS=2 "$vkrt" render "$tmp/fly.cfg" --devices 0,0 -o "$tmp/d/%d/f.png" 2>"$tmp/err"
check "--devices with a file that cannot be written exits 1" test $? -eq 1
check "and names the file" grep -q "^vkrt: device 0 (.*) failed after [0-9]* frames\{0,1\}: $tmp/d/3/f.png: cannot write: Not a directory" "$tmp/err"
check "and leaves no temporary" sh -c "! find '$tmp/d' -name '*.tmp-*' | grep -q ."

# One frame and two devices: one worker renders it, the same bytes as one device.
"$vkrt" render "$tmp/fly.cfg" --frames 5:5 --devices 0,0 -o "$tmp/single%02d.png" 2>"$tmp/err"
check "--devices with a single frame exits 0" test $? -eq 0
check "and starts one worker" test "$(grep -c '^vkrt: device 0 (.*): ' "$tmp/err")" -eq 1
check "the frame has the single device's bytes" cmp -s "$tmp/single05.png" "$tmp/one05.png"

# Bad uses: a device that does not exist is named with the list of those that do; malformed
# lists, --device with --devices and view --devices are refused before any work.
"$vkrt" render "$tmp/fly.cfg" --devices 0,7 -o "$tmp/bad%02d.png" 2>"$tmp/err"
check "--devices 0,7 exits 1" test $? -eq 1
check "and says there is no device 7" grep -q "^vkrt: --devices 0,7: there is no device 7; the 1 device:" "$tmp/err"
check "and lists the devices" grep -q "^0: .*Vulkan" "$tmp/err"
for bad in x 0,,1 '1,' -1 ""; do
    "$vkrt" render "$tmp/fly.cfg" --devices "$bad" -o "$tmp/bad%02d.png" 2>"$tmp/err"
    check "--devices '$bad' is refused" test $? -eq 2
done
"$vkrt" render "$tmp/fly.cfg" --device 0 --devices 0 -o "$tmp/bad%02d.png" 2>"$tmp/err"
check "--device with --devices is refused" grep -q "^vkrt: --device and --devices: give one" "$tmp/err"
"$vkrt" view "$tmp/fly.cfg" --devices 0 2>"$tmp/err"
check "view --devices is refused" grep -q "vkrt view does not take --devices (an option of vkrt render)" "$tmp/err"
check "and nothing was written" sh -c "! ls '$tmp' | grep -q '^bad'"

summary
