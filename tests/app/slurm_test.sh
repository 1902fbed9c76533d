#!/usr/bin/env bash
# tests/app/slurm_test.sh — issue 47 item 9 (docs/shards.md "Slurm"): scripts/slurm_render.sh run by a
# real Slurm. The test starts a one-node cluster of its own (munged, slurmctld and slurmd from
# Debian's slurm-wlm and munge, on loopback, on free ports, every file in its own mktemp -d folder),
# submits an animation as a job array (4 tasks) with sbatch --wait, checks that every task ran
# through Slurm, and compares the files — names and bytes — with one unsharded run. The daemons
# are stopped and the folder removed on every exit.
# Usage: slurm_test.sh AQUARELLE SOURCE_DIR
set -euo pipefail
bin=$(readlink -f "$1")
src=$(readlink -f "$2")
dir=$(mktemp -d "${TMPDIR:-/tmp}/aq_slurm_test.XXXXXX")
export AQUARELLE_CACHE_DIR="$dir/cache"  # never the user's cache (docs/cache.md)
fail() { echo "slurm_test: FAIL: $*" >&2; for f in "$dir"/*.log; do [ -f "$f" ] && { echo "--- $f" >&2; tail -20 "$f" >&2; }; done; exit 1; }
# slurmd launches the tasks as their user and needs root (CI and our machines run as root); anyone
# else gets "skipped" (exit 77, ctest's SKIP_RETURN_CODE), never a pass.
[ "$(id -u)" = 0 ] || { echo "slurm_test: skipped: slurmd needs root"; exit 77; }
for c in munged slurmctld slurmd sbatch sinfo scontrol; do
  command -v "$c" >/dev/null || fail "$c is not installed (scripts/setup.sh installs slurmctld, slurmd, slurm-client and munge)"
done
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$p" 2>/dev/null || true
  done
  rm -rf "$dir"
}
trap cleanup EXIT

# Free TCP ports on loopback for slurmctld and slurmd.
read -r ctld_port slurmd_port < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
node=$(hostname -s)
cpus=$(nproc)
mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
chmod 700 "$dir/munge"

# munge: a key of our own and a socket in our folder (root needs --force).
dd if=/dev/urandom of="$dir/munge/key" bs=1024 count=1 status=none
chmod 400 "$dir/munge/key"
munged --force --key-file="$dir/munge/key" --socket="$dir/munge/socket" --pid-file="$dir/munge/pid" \
  --log-file="$dir/munged.log" --seed-file="$dir/munge/seed"
for _ in $(seq 100); do [ -s "$dir/munge/pid" ] && break; sleep 0.05; done
[ -s "$dir/munge/pid" ] || fail "munged did not start"
pids+=("$(cat "$dir/munge/pid")")

cat >"$dir/slurm.conf" <<EOF
ClusterName=aqtest
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
SlurmdTimeout=60
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=aqtest Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$dir/slurm.conf"
slurmctld -f "$SLURM_CONF" -i
for _ in $(seq 100); do [ -s "$dir/slurmctld.pid" ] && break; sleep 0.05; done
[ -s "$dir/slurmctld.pid" ] || fail "slurmctld did not start"
pids+=("$(cat "$dir/slurmctld.pid")")
slurmd -f "$SLURM_CONF" -N "$node"
for _ in $(seq 100); do [ -s "$dir/slurmd.pid" ] && break; sleep 0.05; done
[ -s "$dir/slurmd.pid" ] || fail "slurmd did not start"
pids+=("$(cat "$dir/slurmd.pid")")
state=""
for _ in $(seq 300); do
  state=$(sinfo -h -N -o %t 2>/dev/null || true)
  [ "$state" = idle ] && break
  sleep 0.1
done
[ "$state" = idle ] || fail "the node is '$state', not idle, 30 s after slurmd started"

# The animation as a 4-task array (each task one shard, one CPU), then one unsharded run.
common=(procedural:swatches --width 96 --height 64 --quiet --frames 0-8)
mkdir -p "$dir/slurm" "$dir/one" "$dir/job"
(cd "$src" && AQ_BIN="$bin" timeout 300 sbatch --wait --quiet --array=0-3 --cpus-per-task=1 \
  --output="$dir/job/task_%a.out" scripts/slurm_render.sh "${common[@]}" --out "$dir/slurm/f_####.png") \
  || fail "the job array failed: $(cat "$dir"/job/*.out 2>/dev/null)"
[ "$(ls "$dir/job" | wc -l)" = 4 ] || fail "$(ls "$dir/job" | wc -l) task outputs, not 4"
"$bin" render "${common[@]}" --out "$dir/one/f_####.png"
(cd "$dir/one" && sha256sum -- *) >"$dir/a.sum"
(cd "$dir/slurm" && sha256sum -- *) >"$dir/b.sum"
[ "$(wc -l <"$dir/a.sum")" = 18 ] || fail "the unsharded run wrote $(wc -l <"$dir/a.sum") files, not 18"
diff "$dir/a.sum" "$dir/b.sum" >&2 || fail "the Slurm array's files differ from one run's"
echo "slurm_test: 4 array tasks under slurmctld/slurmd wrote the 18 files of one run, byte for byte"
