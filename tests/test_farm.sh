#!/bin/sh
# test_farm.sh: tools/farm against a real Slurm: a single-node cluster started here on localhost
# (munged, slurmctld and slurmd of Debian's munge and slurm-wlm, everything in a temporary
# folder), a 12-frame flythrough submitted in 4 tasks of 3 frames. Checked:
#   - every frame arrives byte-identical to a local `vkrt render` of the same scene and options;
#   - a task cancelled while it waits and one cancelled while it runs (scancel) leave frames
#     missing, and so does a frame cut short on disk; `tools/farm wait` and `status` say how
#     many, and `tools/farm resubmit` submits exactly the chunks that hold them (the files on
#     disk decide, listed here independently), after which nothing is missing;
#   - the completeness checks of tools/farm agree with vkrt's (--resume) on whole, cut and
#     wrong-sized PNG and EXR files; submit refuses a pattern without a frame number.
# Exit 77 (skipped) when not root (slurmd runs tasks as their user), without the Debian packages,
# or when the cluster does not come up. Every daemon started here is stopped on exit; every wait
# is bounded. Run by meson test with VKRT_BINARY and VKRT_SOURCE_DIR set.
set -u
vkrt=${VKRT_BINARY:?}
src=${VKRT_SOURCE_DIR:?}
farm="$src/tools/farm"
. "$src/tests/lib.sh"

# Short, because munged's socket path must fit a sockaddr_un (108 bytes).
tmp=$(mktemp -d /tmp/vkrt-farm.XXXXXX)
daemons=""
cleanup() {
    if [ -n "$daemons" ]; then
        # Tasks first: slurmstepd outlives slurmd, so no task may be left running.
        jobs=$(timeout 10 squeue --noheader --format=%A 2>/dev/null)
        [ -n "$jobs" ] && timeout 10 scancel $jobs 2>/dev/null
        deadline=$(($(date +%s) + 10))
        while [ -n "$(timeout 5 squeue --noheader 2>/dev/null)" ] &&
            [ "$(date +%s)" -lt $deadline ]; do
            sleep 0.2
        done
        for pid in $daemons; do kill "$pid" 2>/dev/null; done
        # A daemon that does not stop within 10 s is killed, so that the waits below end.
        (trap 'kill $timer; exit' TERM; sleep 10 & timer=$!; wait $timer; kill -KILL $daemons) \
            >/dev/null 2>&1 &
        watchdog=$!
        for pid in $daemons; do wait "$pid" 2>/dev/null; done
        kill "$watchdog" 2>/dev/null
    fi
    rm -rf "$tmp"
}
trap cleanup EXIT
trap 'exit 1' INT TERM

# A 12-camera flythrough of the Cornell box; a commented-out camera is not a frame.
{
    echo "geometry $src/scenes/cornell/cornell.obj"
    echo "resolution 40 40"
    echo "light point 278 500 279 250000 250000 250000"
    echo "# camera eye 0 273 -800 look 278 273 0 up 0 1 0 fov 40"
    awk 'BEGIN { for (f = 0; f < 12; f++)
        printf "camera eye %d 273 -800 look 278 273 0 up 0 1 0 fov 40  # frame %d\n", 200 + 10 * f, f }'
} >"$tmp/fly.cfg"
mkdir "$tmp/local" "$tmp/farm"
# The local render, beside the rest of the set-up: each vkrt spends most of its time starting.
# tools/farm is given the same options, the size and exposure after its "--": a frame of another
# size would not count as complete, one of another exposure would differ.
"$vkrt" render "$tmp/fly.cfg" --spp 1 --width 32 --height 24 --exposure 1 --quiet \
    -o "$tmp/local/f%02d.png" &
local_render=$!

# The completeness checks (no cluster needed): tools/farm's against what vkrt --resume skips.
"$vkrt" render "$tmp/fly.cfg" --frames 0:0 --width 32 --height 24 --quiet -o "$tmp/w%d.exr" && mv "$tmp/w0.exr" "$tmp/whole.exr"
wait $local_render
check "the local render exits 0" test $? -eq 0
# Cut short by a few bytes: the headers whole, the last chunk of pixels not.
head -c $(($(wc -c <"$tmp/whole.exr") - 10)) "$tmp/whole.exr" >"$tmp/cut.exr"
head -c $(($(wc -c <"$tmp/local/f00.png") - 1)) "$tmp/local/f00.png" >"$tmp/cut.png"
python3 - "$farm" "$tmp" >"$tmp/complete" <<'PY'
import importlib.machinery, sys
farm = importlib.machinery.SourceFileLoader("farm", sys.argv[1]).load_module()
for name, w, h in [("local/f00.png", 32, 24), ("local/f00.png", 24, 32), ("cut.png", 32, 24),
                   ("whole.exr", 32, 24), ("whole.exr", 24, 32), ("cut.exr", 32, 24),
                   ("none.png", 32, 24)]:
    print(name, w, h, farm.frame_is_complete(f"{sys.argv[2]}/{name}", w, h))
PY
check "a whole PNG is complete" grep -q "^local/f00.png 32 24 True$" "$tmp/complete"
check "a PNG of another size is not" grep -q "^local/f00.png 24 32 False$" "$tmp/complete"
check "a PNG cut short is not" grep -q "^cut.png 32 24 False$" "$tmp/complete"
check "a whole EXR is complete" grep -q "^whole.exr 32 24 True$" "$tmp/complete"
check "an EXR of another size is not" grep -q "^whole.exr 24 32 False$" "$tmp/complete"
check "an EXR cut short is not" grep -q "^cut.exr 32 24 False$" "$tmp/complete"
check "a missing file is not" grep -q "^none.png 32 24 False$" "$tmp/complete"
"$farm" submit "$tmp/fly.cfg" --out "$tmp/farm/one.png" --vkrt "$vkrt" --job "$tmp/bad" \
    2>"$tmp/err"
check "submit refuses an output without a frame number" test $? -eq 1
check "and says that the scene has 12 cameras" grep -q "has 12 cameras" "$tmp/err"
check "and leaves no job behind" test ! -e "$tmp/bad/job.json"

finish() { # finish: the summary, and exit 77 if the cluster part could not run
    summary || exit 1
    [ -n "${1:-}" ] || exit 0
    echo "SKIP: $1"
    exit 77
}
[ "$(id -u)" -eq 0 ] || finish "the Slurm part needs root (slurmd runs each task as its user)"
for program in munged slurmctld slurmd sbatch squeue scancel sinfo; do
    command -v $program >/dev/null 2>&1 ||
        finish "$program is missing (Debian: apt-get install slurm-wlm munge)"
done

# The cluster: munged on its own socket and key, slurmctld and slurmd in the foreground (so
# that their process ids are ours to stop) on two free ports of localhost.
dd if=/dev/urandom of="$tmp/munge.key" bs=1024 count=1 2>/dev/null
chmod 400 "$tmp/munge.key"
munged --foreground --force --socket="$tmp/munge.sock" --key-file="$tmp/munge.key" \
    --pid-file="$tmp/munged.pid" --log-file="$tmp/munged.log" --seed-file="$tmp/munged.seed" \
    2>>"$tmp/munged.log" &
daemons="$!"
ports=$(python3 -c 'import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
set -- $ports
host=$(hostname -s)
mkdir "$tmp/spool" "$tmp/state"
# Four GPUs of the generic-resource kind, so that --gpus-per-task 1 is asked and granted: empty
# files stand in for their device files.
: >"$tmp/gpu0" && : >"$tmp/gpu1" && : >"$tmp/gpu2" && : >"$tmp/gpu3"
echo "NodeName=farmnode Name=gpu File=$tmp/gpu[0-3]" >"$tmp/gres.conf"
# No cgroups (a container has none to give): linuxproc tracks a task's processes; sched_interval
# 1 starts a waiting task within a second of another's end, not at the next minute.
cat >"$tmp/slurm.conf" <<CONF
ClusterName=vkrtfarm
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$1
SlurmdPort=$2
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$tmp/munge.sock
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=1
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
GresTypes=gpu
ReturnToService=2
# The node as configured here, whatever the machine has (three tasks at once on two cores).
SlurmdParameters=config_overrides
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
NodeName=farmnode NodeHostname=$host NodeAddr=127.0.0.1 CPUs=3 RealMemory=1000 Gres=gpu:4
PartitionName=render Nodes=farmnode Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$tmp/slurm.conf"
slurmctld -D -i -f "$SLURM_CONF" >/dev/null 2>&1 &
daemons="$daemons $!"
slurmd -D -f "$SLURM_CONF" -N farmnode >/dev/null 2>&1 &
daemons="$daemons $!"
deadline=$(($(date +%s) + 30))
until [ "$(timeout 5 sinfo --noheader --nodes=farmnode --format=%T 2>/dev/null)" = idle ]; do
    if [ "$(date +%s)" -ge $deadline ]; then
        tail -n 5 "$tmp/munged.log" "$tmp/slurmctld.log" "$tmp/slurmd.log" 2>/dev/null
        finish "the single-node Slurm cluster did not come up within 30 s (logs above)"
    fi
    sleep 0.2
done

# Submit 12 frames in 4 tasks; three CPUs run three at a time, so task 3 is still waiting when
# it is cancelled, and task 0 is cancelled once it runs (before, during or after its frames).
"$farm" submit "$tmp/fly.cfg" --out "$tmp/farm/f%02d.png" --chunk 3 --gpus-per-task 1 \
    --partition render --spp 1 --vkrt "$vkrt" --job "$tmp/job" -- --width 32 --height 24 --exposure 1 >"$tmp/submit" 2>&1
status=$?
check "submit exits 0" test $status -eq 0
[ $status -eq 0 ] || cat "$tmp/submit"
check "submit says 12 frames of 32x24" grep -q ": 12 frames of 32x24$" "$tmp/submit"
check "submit makes 4 tasks of 3 frames" grep -q "submitted job [0-9]*: 4 tasks (chunks 0-3) of 3 frames" "$tmp/submit"
job=$(sed -n 's/.*submitted job \([0-9]*\).*/\1/p' "$tmp/submit")
scancel "${job}_3"
deadline=$(($(date +%s) + 30))
running=no
while [ "$(date +%s)" -lt $deadline ]; do
    if timeout 5 squeue --noheader --jobs="${job}_0" --format=%T 2>/dev/null | grep -q RUNNING
    then
        running=yes
        break
    fi
    sleep 0.1
done
check "task 0 ran" test $running = yes
scancel "${job}_0"
"$farm" wait --job "$tmp/job" --poll 0.3 --timeout 120 >"$tmp/wait1" 2>&1
check "wait says frames are missing (exit 1)" test $? -eq 1
check "a task asked for a GPU and got it" grep -q "^tools/farm: task 1 on .*: frames 3 to 5, GPUs: 1$" \
    "$tmp/job/logs/${job}_1.log"
frames_done=$(ls "$tmp/farm" | grep -c '^f..\.png$')
check "wait counts the frames on disk ($frames_done)" \
    grep -q "^farm: $frames_done of 12 frames done; no task queued" "$tmp/wait1"
# A frame cut short (a node lost while it wrote, another tool) is missing too.
head -c 100 "$tmp/local/f04.png" >"$tmp/farm/f04.png"
# Which chunks have missing frames, from the files alone.
expected=""
for chunk in 0 1 2 3; do
    for f in $((3 * chunk)) $((3 * chunk + 1)) $((3 * chunk + 2)); do
        if [ ! -e "$tmp/farm/f0$f.png" ] && [ ! -e "$tmp/farm/f$f.png" ] || [ $f -eq 4 ]; then
            expected="$expected,$chunk"
            break
        fi
    done
done
# In Slurm's --array form, as tools/farm writes it: runs of chunks as "A-B".
expected=$(echo "${expected#,}" | awk -F, '{
    out = $1
    for (i = 2; i <= NF; i++)
        if ($i != $(i - 1) + 1) out = out "," $i
        else if (i == NF || $(i + 1) != $i + 1) out = out "-" $i
    print out }')
check "the waiting task's frames 9-11 are missing" sh -c "echo '$expected' | grep -q 3"
check "the tasks not cancelled delivered theirs" test "$(ls "$tmp/farm" | grep -c '^f0[35678]\.png$')" -eq 5
"$farm" status --job "$tmp/job" >"$tmp/status" 2>&1
check "status counts the cut frame as missing" \
    grep -q "^farm: $((frames_done - 1)) of 12 frames done; no task queued: frames .* missing (chunks $expected;" "$tmp/status"
"$farm" resubmit --job "$tmp/job" >"$tmp/resubmit" 2>&1
check "resubmit exits 0" test $? -eq 0
check "resubmit submits the chunks with missing frames ($expected), no others" \
    grep -q "tasks\? (chunks $expected) of 3 frames" "$tmp/resubmit"
"$farm" wait --job "$tmp/job" --poll 0.3 --timeout 120 >"$tmp/wait2" 2>&1
check "after the resubmission wait exits 0" test $? -eq 0
check "and says all 12 frames are done" grep -q "^farm: 12 of 12 frames done$" "$tmp/wait2"
identical=0
for f in "$tmp/local"/f*.png; do
    cmp -s "$f" "$tmp/farm/$(basename "$f")" && identical=$((identical + 1))
done
check "all 12 frames are byte-identical to the local render ($identical)" test $identical -eq 12
check "no temporary file is left" sh -c "! ls '$tmp/farm' | grep -q tmp"
"$farm" resubmit --job "$tmp/job" >"$tmp/resubmit2" 2>&1
check "resubmit with nothing missing submits nothing" \
    grep -q "all 12 frames are complete; nothing to submit" "$tmp/resubmit2"
finish
