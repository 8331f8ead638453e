#!/usr/bin/env bash
# The Slurm job array of docs/batch.md, run for real: a single-node Slurm (slurmctld, slurmd and
# munged, private to this test: own config, key, socket, ports and state in WORKDIR) runs
# scripts/slurm-batch.sh as 2 shards over 3 tiny models from a folder where logs/ does not exist;
# every task's log is there, every model is built once, the shard summaries merge, and each output
# is byte-identical to an unsharded run. Also: the script in docs/batch.md is the file. Skipped
# (77) with a message where the daemons are missing or cannot start (no root, no munge).
. "$(dirname "$0")/cli_common.sh" "$1" "$2"
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
script=$source_dir/scripts/slurm-batch.sh
skip() { echo "skipped: $*"; exit 77; }

# The documented block is the file, byte for byte.
documented=$(awk '/^### Slurm job array/ {section = 1} section && /^```sh$/ {inside = 1; next} inside && /^```$/ {exit} inside' \
  "$source_dir/docs/batch.md")
[ "$documented" = "$(cat "$script")" ] || fail "the sbatch script in docs/batch.md differs from scripts/slurm-batch.sh"

for tool in munged mungekey slurmctld slurmd sbatch squeue sinfo; do
  command -v "$tool" >/dev/null || [ -x "/usr/sbin/$tool" ] || skip "$tool is not installed (Debian packages slurm-wlm and munge)"
done
[ "$(id -u)" -eq 0 ] || skip "a private slurmd needs root (it starts jobs as their user)"
export PATH=$PATH:/usr/sbin

cluster=$work/cluster
mkdir -p "$cluster/state" "$cluster/spool" "$cluster/munge"
pids=()
stop_daemons() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null; done
}
trap stop_daemons EXIT

# munged with its own key and socket.
mungekey --create --keyfile="$cluster/munge/munge.key" >/dev/null 2>&1 || skip "mungekey cannot make a key"
munged --foreground --force --key-file="$cluster/munge/munge.key" --socket="$cluster/munge/socket" \
  --pid-file="$cluster/munge/pid" --log-file="$cluster/munge/log" --seed-file="$cluster/munge/seed" >"$cluster/munge/out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$cluster/munge/socket" ] && break; sleep 0.1; done
[ -S "$cluster/munge/socket" ] || skip "munged did not start: $(tail -n 3 "$cluster/munge/log" 2>/dev/null)"

# Two free ports for slurmctld and slurmd.
read -r ctld_port slurmd_port < <(python3 -c 'import socket
s = [socket.socket() for _ in range(2)]
[x.bind(("127.0.0.1", 0)) for x in s]
print(*[x.getsockname()[1] for x in s])')
node=$(hostname -s)
cpus=$(nproc --all)
cat >"$cluster/slurm.conf" <<EOF
ClusterName=splatcl-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$cluster/munge/socket
StateSaveLocation=$cluster/state
SlurmdSpoolDir=$cluster/spool
SlurmctldPidFile=$cluster/slurmctld.pid
SlurmdPidFile=$cluster/slurmd.pid
SlurmctldLogFile=$cluster/slurmctld.log
SlurmdLogFile=$cluster/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/affinity
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
MpiDefault=none
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=1000 State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$cluster/slurm.conf
slurmctld -D -i >"$cluster/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D >"$cluster/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do sinfo -h -o '%t' 2>/dev/null | grep -qE '^(idle|mix|alloc)' && break; sleep 0.2; done
sinfo -h -o '%t' 2>/dev/null | grep -qE '^(idle|mix|alloc)' ||
  skip "the single-node Slurm did not come up: $(tail -n 2 "$cluster/slurmctld.log" "$cluster/slurmd.log" 2>/dev/null | tr '\n' ' ')"

# The project folder: three models and a manifest; no logs/ folder, no out/.
project=$work/project
mkdir -p "$project/meshes"
printf '%s\n' "$cube" >"$project/meshes/cube.obj"
printf '%s\n' "$wedge" >"$project/meshes/wedge.obj"
{ printf '%s\n' "$cube"; echo "# another"; } >"$project/meshes/box.obj"
printf '{"defaults": {"maps": 64, "res": 16, "k": 8}, "models": ["meshes/cube.obj", "meshes/wedge.obj", "meshes/box.obj"]}\n' \
  >"$project/set.json"
# splatcl on the PATH. The script puts PoCL's kernel cache in $TMPDIR/pocl-cache-$USER: here that
# is a link to the cache the other tests fill, so the tasks do not compile every kernel again.
export USER=${USER:-$(id -un)}
export PATH=$(dirname "$splatcl"):$PATH TMPDIR=$work/tmp
mkdir -p "$TMPDIR"
shared_cache=${POCL_CACHE_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/pocl/kcache}
mkdir -p "$shared_cache" 2>/dev/null && ln -s "$shared_cache" "$TMPDIR/pocl-cache-$USER"
# The array and the resources fit a small node; everything else is the script's.
(cd "$project" && timeout 120 sbatch --wait --array=0-1 --cpus-per-task=1 --mem=100M --time=5 "$script") >"$work/sbatch.out" 2>&1
status=$?
[ "$status" -eq 0 ] || fail "sbatch --wait exited $status: $(cat "$work/sbatch.out") $(cat "$project"/splatcl-batch-*.log 2>/dev/null)"
logs=("$project"/splatcl-batch-*-[01].log)
[ "${#logs[@]}" -eq 2 ] && [ -s "${logs[0]}" ] && [ -s "${logs[1]}" ] || fail "expected two task logs, found: $(ls "$project")"
[ "$(cat "${logs[@]}" | grep -c '^ok      ')" -eq 3 ] || fail "the two tasks did not build the three models once: $(cat "${logs[@]}")"
"$splatcl" batch merge "$project"/out/summary-*-of-2.json -o "$project/out/summary.json" >/dev/null || fail "the shard summaries do not merge"
grep -q '"ok": 3' "$project/out/summary.json" || fail "the merged summary does not count 3 ok models"
# Byte-identical to an unsharded run outside Slurm.
(cd "$project" && "$splatcl" batch set.json -o "$work/whole" >/dev/null) || fail "the unsharded run failed"
for id in cube wedge box; do
  for file in "$id.splats.ply" "$id.csm"; do
    cmp -s "$project/out/$file" "$work/whole/$file" || fail "$file differs between the Slurm shards and an unsharded run"
  done
done
echo "ok: the documented sbatch script ran 2 shards on a single-node Slurm; logs written without a logs/ folder; outputs identical"
