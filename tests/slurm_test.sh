#!/usr/bin/env bash
# slurm_test.sh: starts a real single-node Slurm cluster in a temporary folder (munged as its own
# user, slurmctld and slurmd as root, no systemd: proctrack/linuxproc, task/none, free ports),
# then renders a scene through tools/slurm/submit.sh as a 4-task job array and a merge job that
# depends on it (afterok), which must give the single render's image byte for byte; and the same
# with a failing task, whose merge must never run and whose parts merged by hand are refused. Everything it started is
# stopped on exit. Exit 77 (skip) where Slurm or munge is not installed, or not as root. First, and
# everywhere, tools/slurm/task.sh is checked on its own. slurm_test.sh TRAZADOR: the binary the
# cluster runs.
set -euo pipefail
trazador=$(realpath "${1:?slurm_test.sh TRAZADOR}")

# tools/slurm/task.sh on its own, with stand-ins for trazador and scontrol (no Slurm needed): the
# sample ranges it cuts, resuming from a checkpoint, and requeueing itself on SIGUSR1.
local_dir=$(mktemp -d /tmp/slurm_task.XXXXXX)
trap 'rm -rf "$local_dir"' EXIT
here=$(dirname "$(realpath "$0")")
cat >"$local_dir/trazador" <<'EOF'
#!/usr/bin/env bash
# Records its arguments; "slow" in them: writes the checkpoint and waits for SIGTERM.
out="" checkpoint=""
for ((i = 1; i <= $#; i++)); do
    case ${!i} in -o) j=$((i + 1)); out=${!j} ;; --checkpoint) j=$((i + 1)); checkpoint=${!j} ;; esac
done
echo "$*" >>"$TRAZADOR_PARTS_DIR/calls.txt"
if [[ " $* " == *" slow "* ]]; then
    trap 'echo checkpointed >"$checkpoint"; exit 0' TERM
    touch "$TRAZADOR_PARTS_DIR/started"
    while :; do sleep 0.05; done
fi
echo part >"$out"
EOF
printf '#!/bin/sh\necho "$*" >>"$TRAZADOR_PARTS_DIR/scontrol.txt"\n' >"$local_dir/scontrol"
chmod 755 "$local_dir/trazador" "$local_dir/scontrol"
task() { # exec: in `task ... &`, $! is task.sh itself
    exec env PATH="$local_dir:$PATH" TRAZADOR_BIN="$local_dir/trazador" TRAZADOR_SCENE=s.scene \
        TRAZADOR_PARTS_DIR="$local_dir" TRAZADOR_PARTS=4 TRAZADOR_SPLIT=samples TRAZADOR_SPP=100 \
        TRAZADOR_SIZE="" SLURM_ARRAY_JOB_ID=41 SLURM_ARRAY_TASK_ID="$1" \
        TRAZADOR_RENDER_FLAGS="$2" "$here/../tools/slurm/task.sh"
}
for i in 0 1 2 3; do (task "$i" "--spp 100") >/dev/null || { echo "slurm_test: FAIL: task $i" >&2; exit 1; }; done
expected="render s.scene --spp 100 --samples 0:16 --checkpoint $local_dir/checkpoint_0.exr -o $local_dir/part_0.exr
render s.scene --spp 100 --samples 16:48 --checkpoint $local_dir/checkpoint_1.exr -o $local_dir/part_1.exr
render s.scene --spp 100 --samples 48:64 --checkpoint $local_dir/checkpoint_2.exr -o $local_dir/part_2.exr
render s.scene --spp 100 --samples 64:100 --checkpoint $local_dir/checkpoint_3.exr -o $local_dir/part_3.exr"
[ "$(cat "$local_dir/calls.txt")" = "$expected" ] ||
    { echo "slurm_test: FAIL: task.sh ran: $(cat "$local_dir/calls.txt")" >&2; exit 1; }
(task 2 "") | grep -q "already rendered" || { echo "slurm_test: FAIL: a done part ran again" >&2; exit 1; }
rm "$local_dir/part_2.exr" "$local_dir/calls.txt"
task 2 "slow 'two words'" >/dev/null &
task_pid=$!
for _ in $(seq 100); do [ -e "$local_dir/started" ] && break; sleep 0.05; done
kill -USR1 "$task_pid"
for _ in $(seq 100); do kill -0 "$task_pid" 2>/dev/null || break; sleep 0.05; done
if kill -0 "$task_pid" 2>/dev/null; then
    kill -TERM "$task_pid"
    echo "slurm_test: FAIL: task.sh did not stop on SIGUSR1" >&2
    exit 1
fi
wait "$task_pid" || { echo "slurm_test: FAIL: the requeued task failed" >&2; exit 1; }
[ "$(cat "$local_dir/scontrol.txt" 2>/dev/null)" = "requeue 41_2" ] &&
    [ "$(cat "$local_dir/checkpoint_2.exr")" = checkpointed ] && [ ! -e "$local_dir/part_2.exr" ] ||
    { echo "slurm_test: FAIL: USR1 did not checkpoint and requeue" >&2; exit 1; }
(task 2 "'two words'") >/dev/null
[ "$(tail -n 1 "$local_dir/calls.txt")" = "render s.scene two words --samples 48:64 --resume $local_dir/checkpoint_2.exr --checkpoint $local_dir/checkpoint_2.exr -o $local_dir/part_2.exr" ] &&
    [ ! -e "$local_dir/checkpoint_2.exr" ] && [ -s "$local_dir/part_2.exr" ] ||
    { echo "slurm_test: FAIL: the requeued task did not resume: $(tail -n 1 "$local_dir/calls.txt")" >&2; exit 1; }
rm -rf "$local_dir"
trap - EXIT
echo "slurm_test: task.sh cuts, resumes and requeues"

for tool in munged mungekey slurmctld slurmd sbatch scontrol sinfo setpriv; do
    if ! command -v "$tool" >/dev/null 2>&1 && ! [ -x "/usr/sbin/$tool" ]; then
        echo "slurm_test: $tool is not installed (Debian: slurmctld slurmd slurm-client munge); skipped"
        exit 77
    fi
done
if [ "$(id -u)" != 0 ]; then
    echo "slurm_test: slurmd runs jobs as their users and needs root; skipped"
    exit 77
fi
export PATH="$PATH:/usr/sbin"

start=$(date +%s.%N)
dir=$(mktemp -d /tmp/slurm_test.XXXXXX)
pids=()
cleanup() {
    local rc=$?
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    for pid in "${pids[@]}"; do
        for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$pid" 2>/dev/null || true
    done
    if [ "$rc" != 0 ] && [ "$rc" != 77 ]; then
        for log in "$dir"/log/*.log; do echo "== $log"; tail -n 20 "$log"; done
    fi
    rm -rf "$dir"
    exit "$rc"
}
trap cleanup EXIT
trap 'exit 1' INT TERM

fail() {
    echo "slurm_test: FAIL: $*" >&2
    exit 1
}

# A TCP port nothing listens on (from /proc/net/tcp{,6}), not among those already chosen.
taken=""
free_port() {
    local listening port
    listening=$(awk 'NR > 1 && $4 == "0A" { split($2, a, ":"); print strtonum("0x" a[2]) }' \
        /proc/net/tcp /proc/net/tcp6 2>/dev/null | sort -u)
    while :; do
        port=$((20000 + RANDOM % 40000))
        if ! grep -qx "$port" <<<"$listening" && ! grep -qw "$port" <<<"$taken"; then
            taken="$taken $port"
            echo "$port"
            return
        fi
    done
}

# Polls `cmd` every 0.1 s until it succeeds, for at most $1 seconds.
wait_for() {
    local limit=$1
    shift
    local deadline=$(($(date +%s) + limit))
    until "$@" >/dev/null 2>&1; do
        [ "$(date +%s)" -lt "$deadline" ] || return 1
        sleep 0.1
    done
}

mkdir -p "$dir"/{munge,state,spool,log}
chmod 755 "$dir"
host=$(hostname -s)
cpus=$(nproc)

# munge: a fresh key, its folder owned by the munge user, munged in the foreground as that user.
chown munge: "$dir/munge"
chmod 700 "$dir/munge"
setpriv --reuid=munge --regid=munge --init-groups mungekey --create --keyfile="$dir/munge/munge.key"
setpriv --reuid=munge --regid=munge --init-groups munged --foreground --force \
    --socket="$dir/munge/munge.socket" --key-file="$dir/munge/munge.key" \
    --pid-file="$dir/munge/munged.pid" --seed-file="$dir/munge/munged.seed" \
    --log-file="$dir/log/munged.log" >"$dir/log/munged.out" 2>&1 &
pids+=($!)
wait_for 10 test -S "$dir/munge/munge.socket" || fail "munged did not start"
chmod 755 "$dir/munge"

export SLURM_CONF="$dir/slurm.conf"
cat >"$SLURM_CONF" <<EOF
ClusterName=trazador
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/builtin
SchedulerParameters=batch_sched_delay=0,sched_interval=1
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SlurmdParameters=config_overrides
ReturnToService=2
MpiDefault=none
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
# sbatch --wait polls every 2 s only while MinJobAge allows it (its polls grow to 10 s otherwise).
MinJobAge=4
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF

slurmctld -D -i -f "$SLURM_CONF" >"$dir/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$dir/log/slurmd.out" 2>&1 &
pids+=($!)
node_idle() { [ "$(sinfo -h -n "$host" -o %T 2>/dev/null)" = idle ]; }
wait_for 30 node_idle || fail "the node did not come up idle: $(sinfo -h -o '%T %E' 2>&1)"
ready=$(date +%s.%N)
printf 'slurm_test: cluster up in %.1f s (node %s, %s CPUs)\n' "$(echo "$ready - $start" | bc)" \
    "$host" "$cpus"

# tools/slurm/submit.sh with the real trazador: a 4-task array (bands of rows) and the merge job
# after it, waited for with sbatch --wait; the merged image is byte for byte the single render.
jobs="$dir/jobs"
flags=(--backend cpu --width 40 --spp 40)
cp "$here/../scenes/cornell.scene" "$dir/scene.scene"
"$trazador" render "$dir/scene.scene" "${flags[@]}" --quiet -o "$dir/single.pfm" ||
    fail "the single render failed"
(cd "$dir" && "$here/../tools/slurm/submit.sh" --wait --parts 4 --size 40x40 \
    --trazador "$trazador" --dir "$jobs" scene.scene "$dir/merged.pfm" -- "${flags[@]}" \
    >"$dir/submit.out") ||
    fail "the merge job failed: $(cat "$dir/submit.out" "$jobs/logs/"*.log 2>/dev/null)"
cmp -s "$dir/single.pfm" "$dir/merged.pfm" ||
    fail "the merged image is not the single render: $(cat "$jobs/logs/"*.log)"
grep -q "^merge: job [0-9]* -> $dir/merged.pfm$" "$dir/submit.out" ||
    fail "submit.sh printed: $(cat "$dir/submit.out")"
for i in 0 1 2 3; do
    [ -s "$jobs/part_$i.exr" ] && [ ! -e "$jobs/checkpoint_$i.exr" ] ||
        fail "part $i: no part file, or its checkpoint left behind"
done

# A failing part (task 2 resumes from a damaged checkpoint): the merge job is cancelled, never
# run, and the parts merged by hand are refused, the missing band listed. The end is polled:
# sbatch --wait exits 0 for a job cancelled before it started, and polls only every 10 s.
job_state() { scontrol -o show job "$1" | grep -o 'JobState=[A-Z_]*' | cut -d= -f2; }
job_ended() { case $(job_state "$1") in PENDING | RUNNING | CONFIGURING | COMPLETING) return 1 ;; esac; }
bad_jobs="$dir/bad_jobs"
mkdir -p "$bad_jobs"
echo "not an EXR file" >"$bad_jobs/checkpoint_2.exr"
(cd "$dir" && "$here/../tools/slurm/submit.sh" --parts 4 --size 40x40 --trazador "$trazador" \
    --dir "$bad_jobs" scene.scene "$dir/bad.pfm" -- "${flags[@]}" >"$dir/bad_submit.out") ||
    fail "submit.sh failed: $(cat "$dir/bad_submit.out")"
after=$(sed -n 's/^merge: job \([0-9]*\) .*/\1/p' "$dir/bad_submit.out")
[ -n "$after" ] || fail "submit.sh printed: $(cat "$dir/bad_submit.out")"
wait_for 60 job_ended "$after" || fail "the merge after a failed part is still $(job_state "$after")"
state=$(job_state "$after")
[ "$state" = CANCELLED ] || fail "a merge that depends on a failed part ended $state"
[ ! -e "$dir/bad.pfm" ] || fail "a merge that depends on a failed part ran"
grep -q "not an EXR file" "$bad_jobs/logs/part_2.log" ||
    fail "part 2's log: $(cat "$bad_jobs/logs/part_2.log")"
if "$trazador" merge "$bad_jobs"/part_*.exr -o "$dir/bad.pfm" 2>"$dir/bad_merge.err"; then
    fail "the merge of 3 parts of 4 succeeded"
fi
grep -q "region 0,40,20,30 samples 0:40" "$dir/bad_merge.err" ||
    fail "the refused merge said: $(cat "$dir/bad_merge.err")"
printf 'slurm_test: passed in %.1f s\n' "$(echo "$(date +%s.%N) - $start" | bc)"
