#!/usr/bin/env bash
# `penumbra run --shard auto` under a real Slurm (Debian's slurm-wlm and munge): starts munged, slurmctld and slurmd
# on this host (no systemd; key, config, state and logs in SCRATCH, ports from the pid), submits an array of 4 shards,
# 2 at a time, checks `penumbra status` and the outputs, resubmits (everything skipped), cancels a running array with
# scancel (no partial output, the shard exits 75) and resubmits to completion, lets a time limit send the early
# signal (exit 75) and resubmits to completion, then stops the daemons it started by their pids.
# Usage: slurm_test.sh PENUMBRA SCRATCH. Exit 77 (skipped) only when Slurm or munge is not installed.
set -u
bin=$(realpath "$1")
s=$2
for tool in munged mungekey slurmctld slurmd sbatch squeue scancel sinfo; do
  command -v "$tool" >/dev/null || { echo "SKIP: $tool is missing (scripts/setup.sh installs slurm-wlm and munge)"; exit 77; }
done
rm -rf "$s" && mkdir -p "$s"/{state,spool,log,munge,jobs} && chmod 700 "$s/munge"
s=$(realpath "$s")
source "$(dirname "$0")/expect.sh"
pids=()
stop_daemons() {
  [ -n "${SLURM_CONF:-}" ] && scancel --quiet --user "$(id -un)" 2>/dev/null
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null; done
}
trap stop_daemons EXIT
fail_with_logs() {
  echo "FAIL $1"; tail -n 20 "$s"/log/*.log "$s"/munge/*.log 2>/dev/null; exit 1
}

# munge: its own key and socket (-f: the key's folder lives in a build tree).
mungekey -c -k "$s/munge/munge.key" || fail_with_logs "mungekey"
munged -F -f --key-file="$s/munge/munge.key" --socket="$s/munge/munge.sock" --pid-file="$s/munge/munged.pid" \
  --log-file="$s/munge/munged.log" --seed-file="$s/munge/munged.seed" >>"$s/munge/munged.out" 2>&1 &
pids+=($!)

# Slurm: one node, this host; the daemons run as the current user where it is not root (jobs of that user only).
host=$(hostname -s)
user=$(id -un)
port=$((20000 + ($$ % 10000) * 2))
cat >"$s/slurm.conf" <<CONF
ClusterName=penumbra-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$s/munge/munge.sock
CredType=cred/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
StateSaveLocation=$s/state
SlurmdSpoolDir=$s/spool
SlurmctldPidFile=$s/slurmctld.pid
SlurmdPidFile=$s/slurmd.pid
SlurmctldLogFile=$s/log/slurmctld.log
SlurmdLogFile=$s/log/slurmd.log
ReturnToService=2
KillWait=20
InactiveLimit=0
NodeName=$host NodeAddr=127.0.0.1 CPUs=2 RealMemory=500 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$s/slurm.conf
for _ in $(seq 1 50); do [ -S "$s/munge/munge.sock" ] && break; sleep 0.1; done
slurmctld -D -i -f "$SLURM_CONF" >>"$s/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N "$host" >>"$s/log/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 1 120); do [ "$(sinfo -h -o %T 2>/dev/null)" = idle ] && break; sleep 0.5; done
[ "$(sinfo -h -o %T 2>/dev/null)" = idle ] || fail_with_logs "the node never became idle"

# 8 small jobs: 4 shards of 2, 2 shards at a time.
for i in $(seq 0 7); do
  printf '{"scene": "builtin:box", "technique": "pcf", "size": "64x64", "map-size": 128, "png": "none", "camera": "%s,3,6:0,0,0:50", "output": "f%02d.exr"}\n' "$i" "$i"
done >"$s/jobs.jsonl"
cat >"$s/shard.sh" <<SH
#!/usr/bin/env bash
exec "$bin" run "\$1" --out "\$2" --shard auto
SH
chmod +x "$s/shard.sh"
submit() {  # submit MANIFEST OUT [sbatch options]: the array job's id
  local manifest=$1 out=$2
  shift 2
  sbatch --parsable --array=0-3%2 --job-name=penumbra --output="$s/jobs/%A_%a.out" --chdir="$s" "$@" \
    "$s/shard.sh" "$manifest" "$out"
}
expect sbatch-wait 0 '^[0-9]+$' -- timeout 120 bash -c "$(declare -f submit); s='$s' submit '$s/jobs.jsonl' '$s/out' --wait"
expect slurm-status 0 "8 jobs: 8 done, 0 stale, 0 failed, 0 missing" -- "$bin" status "$s/jobs.jsonl" --out "$s/out"
expect slurm-shard-files 0 '^4$' -- bash -c "ls '$s'/out/penumbra-status/shard-?-of-4.jsonl | wc -l"
expect slurm-hosts 0 "\"host\":\"$host\"" -- cat "$s/out/penumbra-status/shard-0-of-4.jsonl"
expect slurm-outputs 0 '^8$' -- bash -c "ls '$s'/out/f0?.exr | wc -l"
expect slurm-resubmit 0 '^[0-9]+$' -- timeout 120 bash -c "$(declare -f submit); s='$s' submit '$s/jobs.jsonl' '$s/out' --wait"
expect slurm-resubmit-skipped 0 '^8$' -- bash -c "cat '$s'/out/penumbra-status/*.jsonl | grep -c '\"state\":\"skipped\"'"

# A resubmission of chosen indices (`--array=1,3` of the array 0-3) with --shard-count 4: tasks 1 and 3 run shards 1
# and 3 of 4 (without the count, task 3 was shard 1 of 2, or refused).
cat >"$s/shard4.sh" <<SH
#!/usr/bin/env bash
exec "$bin" run "\$1" --out "\$2" --shard auto --shard-count 4
SH
chmod +x "$s/shard4.sh"
expect slurm-chosen-indices 0 '^[0-9]+$' -- timeout 120 sbatch --parsable --wait --array=1,3 --job-name=penumbra \
  --output="$s/jobs/%A_%a.out" --chdir="$s" "$s/shard4.sh" "$s/jobs.jsonl" "$s/chosen"
expect slurm-chosen-shards 0 '^shard-1-of-4.jsonl shard-3-of-4.jsonl$' -- bash -c "cd '$s/chosen/penumbra-status' && ls *.jsonl | paste -sd' '"
expect slurm-chosen-outputs 0 '^f01.exr f03.exr f05.exr f07.exr$' -- bash -c "cd '$s/chosen' && ls *.exr | paste -sd' '"

# Cancel a running array (heavier frames: each shard runs for seconds, 20 jobs of ~0.2 s on the 2-core CI machine;
# 10 jobs at 128x96 and 512^2 took half a second a shard, so a shard could finish between its first output and the
# scancel, and no shard was left to say it was stopped), then resubmit to completion.
for i in $(seq 0 79); do
  printf '{"scene": "builtin:box", "technique": "pcss", "size": "320x240", "map-size": 4096, "camera": "%s,3,6:0,0,0:50", "output": "c%02d.exr"}\n' "$i" "$i"
done >"$s/long.jsonl"
job=$(submit "$s/long.jsonl" "$s/cancel")
for _ in $(seq 1 600); do compgen -G "$s/cancel/c*.exr" >/dev/null && break; sleep 0.1; done
scancel "$job"
for _ in $(seq 1 300); do [ -z "$(squeue -h -j "$job" 2>/dev/null)" ] && break; sleep 0.2; done
expect scancel-gone 0 '^$' -- squeue -h -j "$job"
expect scancel-sigterm 0 "left \(SIGTERM\)" -- cat "$s"/jobs/"$job"_*.out
expect scancel-no-partial 0 '^0$' -- bash -c "find '$s/cancel' -name '*.tmp-*' | wc -l"
expect scancel-missing 75 "80 jobs: [0-9]+ done, 0 stale, 0 failed, [1-9][0-9]* missing" -- "$bin" status "$s/long.jsonl" --out "$s/cancel"
expect scancel-resubmit 0 '^[0-9]+$' -- timeout 150 bash -c "$(declare -f submit); s='$s' submit '$s/long.jsonl' '$s/cancel' --wait"
expect scancel-complete 0 "80 jobs: 80 done, 0 stale, 0 failed, 0 missing" -- "$bin" status "$s/long.jsonl" --out "$s/cancel"

# The signal `sbatch --signal=B:TERM@...` sends before a time limit goes to the batch shell only: `exec` in the
# script (shard.sh, docs/batch.md's --wrap) makes penumbra that shell, so it stops early (exit 75) instead of being
# killed at the limit. `scancel --batch --signal=TERM` delivers the same signal the same way.
job=$(submit "$s/long.jsonl" "$s/batchsig")
for _ in $(seq 1 600); do compgen -G "$s/batchsig/c*.exr" >/dev/null && break; sleep 0.1; done
scancel --batch --signal=TERM "$job"
for _ in $(seq 1 900); do [ -z "$(squeue -h -j "$job" 2>/dev/null)" ] && break; sleep 0.2; done
expect batch-signal-reaches-penumbra 0 "left \(SIGTERM\)" -- cat "$s"/jobs/"$job"_*.out
expect batch-signal-resubmit 0 '^[0-9]+$' -- timeout 150 bash -c "$(declare -f submit); s='$s' submit '$s/long.jsonl' '$s/batchsig' --wait"
expect batch-signal-complete 0 "80 jobs: 80 done, 0 stale, 0 failed, 0 missing" -- "$bin" status "$s/long.jsonl" --out "$s/batchsig"

# A time limit that triggers the early signal, submitted as docs/batch.md does (`--time`, `--signal=B:TERM@...`, a
# `--wrap` that execs penumbra). slurmctld tests time limits every 30 s (its PERIODIC_TIMEOUT) and sends the warning
# signal at the first test inside the lead time, so a one-minute limit with the signal asked 60 s ahead reaches
# penumbra within 30 s of the start, long before the limit's kill (60-90 s, then KillWait). The manifest holds about a
# minute of frames on the 2-core CI machine (280 of ~0.22 s), so the shard is still working when the signal comes:
# it finishes the frame in hand and exits 75 (FAILED, not TIMEOUT), and a resubmission renders the rest.
for i in $(seq 0 279); do
  printf '{"scene": "builtin:box", "technique": "pcss", "size": "640x480", "map-size": 4096, "png": "none", "camera": "%s,3,6:0,0,0:50", "output": "t%03d.exr"}\n' "$((i % 20 - 10))" "$i"
done >"$s/timed.jsonl"
timed() {  # timed MINUTES: a job limited to MINUTES with the signal asked 60 s before its end; the job's id
  sbatch --parsable --time="$1" --signal=B:TERM@60 --job-name=penumbra --output="$s/jobs/timed-%j.out" --chdir="$s" \
    "${@:2}" --wrap "exec '$bin' run '$s/timed.jsonl' --out '$s/timed'"
}
job=$(timed 1)
for _ in $(seq 1 900); do [ -z "$(squeue -h -j "$job" 2>/dev/null)" ] && break; sleep 0.2; done
expect timelimit-signal 0 "left \(SIGTERM\)" -- cat "$s/jobs/timed-$job.out"
expect timelimit-exit-75 0 "JobState=FAILED .*ExitCode=75:0" -- bash -c "scontrol show job '$job' | tr -s ' \n' ' '"
expect timelimit-missing 75 "280 jobs: [0-9]+ done, 0 stale, 0 failed, [1-9][0-9]* missing" -- \
  "$bin" status "$s/timed.jsonl" --out "$s/timed"
expect timelimit-no-partial 0 '^0$' -- bash -c "find '$s/timed' -name '*.tmp-*' | wc -l"
expect timelimit-resubmit 0 '^[0-9]+$' -- timeout 300 bash -c "$(declare -f timed); s='$s' bin='$bin' timed 5 --wait"
expect timelimit-complete 0 "280 jobs: 280 done, 0 stale, 0 failed, 0 missing" -- \
  "$bin" status "$s/timed.jsonl" --out "$s/timed"

finish
