#!/usr/bin/env bash
# Slurm, for real (issue 43): a one-node cluster of Debian's slurm-wlm and munge,
# on localhost, with every file (key, sockets, state, logs) in a temporary folder,
# runs scripts/slurm_sweep.sh on tests/bench/data/slurm_sweep.yaml (6 cases, 4
# shards) and checks that
#   1. the merged results.csv and summary.json are byte-identical to an unsharded run;
#   2. resubmitting the finished array computes nothing (every task says
#      "0 computed", no case file is rewritten);
#   3. a cancelled task (1, cancelled while held) and a failed one (2: its output
#      folder is a file) are named by the merge ("missing shards: 1/4 2/4", exit 2),
#      and resubmitting only those two completes the merge, again byte-identical.
# The daemons stop (by their pid files) when the test exits or is interrupted; those
# of a run killed outright are stopped by the next run. Exit 77 (skipped, with the
# reason) when Slurm is not installed or its cluster does not start.
#
# Usage: slurm_cluster_test.sh GRAPEBENCH_BINARY TEMP_FOLDER
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 GRAPEBENCH_BINARY TEMP_FOLDER" >&2; exit 2; }
gb="$(realpath "$1")"
tmp="$(realpath -m "$2")"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)"
scene="$root/tests/bench/data/slurm_sweep.yaml"
sweep="$root/scripts/slurm_sweep.sh"
t_start=$SECONDS

skip() {
  echo "SKIP: $*"
  exit 77
}
for tool in munged mungekey slurmctld slurmd sbatch squeue scontrol scancel sinfo; do
  command -v "$tool" >/dev/null ||
    skip "$tool not found: Debian's slurm-wlm and munge are not installed (scripts/setup.sh installs them)"
done
# slurmd runs each job as its submitter: it must be root.
[ "$(id -u)" -eq 0 ] || skip "slurmd needs root to run jobs; this test runs as $(id -un)"

c="$tmp/cluster"
export SLURM_CONF="$c/slurm.conf"

# Stops the daemon named $2 whose pid file is $1 (only if that pid is still it).
stop_pid_file() {
  local f="$1" pid
  [ -s "$f" ] || return 0
  pid="$(cat "$f")"
  [[ "$(cat "/proc/$pid/comm" 2>/dev/null)" == "$2"* ]] || return 0
  kill -TERM "$pid" 2>/dev/null || return 0
  for _ in $(seq 50); do
    kill -0 "$pid" 2>/dev/null || return 0
    sleep 0.2
  done
  kill -KILL "$pid" 2>/dev/null || true
}
cleanup() {
  local rc=$?
  set +e
  # Jobs first, so no slurmstepd or grapebench outlives the daemons.
  if [ -s "$c/slurmctld.pid" ] && kill -0 "$(cat "$c/slurmctld.pid")" 2>/dev/null; then
    scancel --quiet --user "$(id -un)" 2>/dev/null
    for _ in $(seq 50); do
      [ -z "$(squeue -h 2>/dev/null)" ] && break
      sleep 0.2
    done
  fi
  stop_daemons
  echo "cluster stopped; the test took $((SECONDS - t_start)) s"
  exit "$rc"
}
stop_daemons() {
  stop_pid_file "$c/slurmd.pid" slurmd
  stop_pid_file "$c/slurmctld.pid" slurmctld
  stop_pid_file "$c/munge/munged.pid" munged
}
# A run killed outright (SIGKILL: ctest's timeout) could not stop its daemons: now.
stop_daemons
rm -rf "$tmp"
mkdir -p "$c/munge" "$c/state" "$c/spool" "$c/log"
chmod 700 "$tmp" "$c" "$c/munge"
trap cleanup EXIT
trap 'exit 130' INT TERM

logs() {
  for f in "$@"; do
    [ -f "$f" ] && { echo "--- $f"; tail -n 30 "$f"; }
  done
  return 0
}
fail() {
  echo "FAIL: $*"
  logs "$c"/log/*.log
  exit 1
}

# munge: its own key, socket, pid, seed and log in the temporary folder.
mungekey --create --keyfile "$c/munge/munge.key" || skip "mungekey cannot create a key"
chmod 400 "$c/munge/munge.key"
munged --force --key-file "$c/munge/munge.key" --socket "$c/munge/munge.sock" --pid-file "$c/munge/munged.pid" \
  --log-file "$c/munge/munged.log" --seed-file "$c/munge/munged.seed" ||
  { logs "$c/munge/munged.log"; skip "munged does not start"; }

# Two free ports above 16000, different for each run of the test.
free_port() {
  local p
  for _ in $(seq 100); do
    p=$((20000 + RANDOM % 20000))
    [ -z "$(ss -Hltn "sport = :$p" 2>/dev/null)" ] && [ -z "$(ss -Hltn "sport = :$((p + 1))" 2>/dev/null)" ] &&
      { echo "$p"; return; }
  done
  echo 0
}
port="$(free_port)"
[ "$port" -gt 0 ] || skip "no two free ports above 20000"
host="$(hostname -s)"
cat >"$SLURM_CONF" <<EOF
ClusterName=grapebench-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$c/munge/munge.sock
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
# Jobs start at once, not in the default 3 s batches (this cluster runs only the test).
SchedulerParameters=batch_sched_delay=0
StateSaveLocation=$c/state
SlurmdSpoolDir=$c/spool
SlurmctldPidFile=$c/slurmctld.pid
SlurmdPidFile=$c/slurmd.pid
SlurmctldLogFile=$c/log/slurmctld.log
SlurmdLogFile=$c/log/slurmd.log
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -f "$SLURM_CONF" || { logs "$c/log/slurmctld.log"; skip "slurmctld does not start"; }
slurmd -f "$SLURM_CONF" || { logs "$c/log/slurmd.log"; skip "slurmd does not start"; }
for _ in $(seq 100); do
  [ "$(sinfo -h -o %T 2>/dev/null)" = idle ] && break
  sleep 0.2
done
[ "$(sinfo -h -o %T 2>/dev/null)" = idle ] ||
  { sinfo; logs "$c"/log/*.log; skip "the node did not come up idle in 20 s"; }
echo "cluster up: node $host idle after $((SECONDS - t_start)) s (ports $port, $((port + 1)))"

# Waits until the job (every element of an array) has left the queue.
wait_job() {
  for _ in $(seq 1200); do
    [ -z "$(squeue -h -j "$1" 2>/dev/null)" ] && return 0
    sleep 0.25
  done
  fail "job $1 still queued after 300 s"
}
# "STATE EXIT" of each element of job $1 (one line for a plain job).
job_states() {
  scontrol -o show job "$1" | sed -E 's/.*JobState=([A-Z_]+).* ExitCode=([0-9:]+).*/\1 \2/'
}
# "TASK STATE EXIT" of each task of array job $1 still on record, by task.
task_states() {
  scontrol -o show job "$1" | sed -E 's/.* ArrayTaskId=([0-9]+) .* JobState=([A-Z_]+) .* ExitCode=([0-9:]+) .*/\1 \2 \3/' |
    sort -n
}
# Submits with slurm_sweep.sh (its arguments), sets $array and $merge.
submit() {
  local text
  text="$(GRAPEBENCH="$gb" bash "$sweep" "$@")" || fail "slurm_sweep.sh $*"
  echo "$text"
  array="$(sed -n 's/^array job: \([0-9]*\).*/\1/p' <<<"$text")"
  merge="$(sed -n 's/^merge job: \([0-9]*\).*/\1/p' <<<"$text")"
  if [ -z "$array" ] || [ -z "$merge" ]; then fail "no job ids in: $text"; fi
}
same_as_unsharded() {
  for f in results.csv summary.json; do
    cmp "$1/merged/$f" "$tmp/whole/slurm_sweep/$f" || fail "$1/merged/$f differs from the unsharded run's"
  done
}
case_times() { find "$@" -path '*/cases/*.json' -printf '%p %T@\n' | sort; }

"$gb" run "$scene" --out "$tmp/whole" --threads 1 -q >/dev/null || fail "the unsharded run"

# 1. The array and its merge: the unsharded run's bytes.
submit "$scene" --shards 4 --out "$tmp/a" --threads 1
wait_job "$array"
wait_job "$merge"
[ "$(job_states "$merge")" = "COMPLETED 0:0" ] || { logs "$tmp"/a/logs/*; fail "merge job: $(job_states "$merge")"; }
all4="0 COMPLETED 0:0,1 COMPLETED 0:0,2 COMPLETED 0:0,3 COMPLETED 0:0,"
[ "$(task_states "$array" | tr '\n' ',')" = "$all4" ] || fail "array tasks: $(task_states "$array")"
same_as_unsharded "$tmp/a"
echo "ok: 4 shards merged byte-identical to the unsharded run"

# 2. The finished array again: nothing computed, no case file rewritten.
before="$(case_times "$tmp/a/shards")"
first_array=$array
submit "$scene" --shards 4 --out "$tmp/a" --threads 1
wait_job "$array"
wait_job "$merge"
[ "$(job_states "$merge")" = "COMPLETED 0:0" ] || { logs "$tmp"/a/logs/*; fail "merge job: $(job_states "$merge")"; }
[ "$(task_states "$array" | tr '\n' ',')" = "$all4" ] || fail "array tasks: $(task_states "$array")"
for i in 0 1 2 3; do
  grep -Eq '^[0-9]+ cases: 0 computed, [12] reused' "$tmp/a/logs/${array}_$i.out" ||
    { logs "$tmp/a/logs/${array}_$i.out"; fail "task $i of the resubmitted array computed cases"; }
done
[ "$(case_times "$tmp/a/shards")" = "$before" ] || fail "the resubmitted array rewrote case files"
grep -h ' cases: ' "$tmp/a/logs/${first_array}"_*.out "$tmp/a/logs/${array}"_*.out
same_as_unsharded "$tmp/a"
echo "ok: the finished array resubmitted computed nothing"

# 3. Task 1 cancelled while held, task 2 failing (its output folder is a file).
mkdir -p "$tmp/b/shards"
: >"$tmp/b/shards/2"
submit "$scene" --shards 4 --out "$tmp/b" --threads 1 -- --hold
scancel "${array}_1"
scontrol release "$array"
scontrol release "$merge"
wait_job "$array"
wait_job "$merge"
# A task cancelled before it started leaves no record of its own (nor a log).
states="$(task_states "$array" | tr '\n' ',')"
[ "$states" = "0 COMPLETED 0:0,2 FAILED 2:0,3 COMPLETED 0:0," ] || fail "array tasks: $states"
[ ! -e "$tmp/b/logs/${array}_1.out" ] || fail "the cancelled task 1 ran"
[ "$(job_states "$merge")" = "FAILED 2:0" ] || { logs "$tmp"/b/logs/*; fail "merge job: $(job_states "$merge") (expected exit 2)"; }
merge_log="$tmp/b/logs/merge_$merge.out"
echo "the merge says:"
cat "$merge_log"
grep -q '^  missing shards: 1/4 2/4$' "$merge_log" || fail "the merge does not name shards 1/4 and 2/4"
grep -q "$tmp/b/shards/1/slurm_sweep (absent)" "$merge_log" || fail "the merge does not name shards/1's folder"
before="$(case_times "$tmp/b/shards")"
rm "$tmp/b/shards/2"
submit "$scene" --shards 4 --out "$tmp/b" --threads 1 --tasks 1,2
wait_job "$array"
wait_job "$merge"
[ "$(task_states "$array" | tr '\n' ',')" = "1 COMPLETED 0:0,2 COMPLETED 0:0," ] ||
  fail "resubmitted tasks: $(task_states "$array")"
[ "$(job_states "$merge")" = "COMPLETED 0:0" ] || { logs "$tmp"/b/logs/*; fail "merge job: $(job_states "$merge")"; }
ran=("$tmp/b/logs/${array}"_*.out)
[ "${#ran[@]}" -eq 2 ] || fail "the resubmission ran other tasks than 1 and 2: ${ran[*]}"
[ "$(case_times "$tmp/b/shards/0" "$tmp/b/shards/3")" = "$before" ] || fail "tasks 0 and 3's cases were rewritten"
same_as_unsharded "$tmp/b"
echo "ok: the cancelled and the failed task, resubmitted alone, completed the merge byte-identical"
