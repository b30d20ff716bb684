#!/usr/bin/env bash
# A real Slurm: scripts/cluster/slurm-localhost.sh starts munged, slurmctld and slurmd on this
# machine (state in a temp dir); scripts/cluster/submit.sh submits the array of 4 shards and the
# merge job (--dependency=afterok); the merged sweep equals the unsharded one byte for byte.
source "$(dirname "$0")/common.sh"
for tool in munged mungekey slurmctld slurmd sbatch scontrol; do
  command -v "$tool" >/dev/null || skip "$tool is not installed (slurm-wlm, munge: scripts/install-deps.sh)"
done
[[ $(id -u) -eq 0 ]] || skip "a one-node Slurm needs root here (slurmd)"
sweep=(--spp 16 --res 72x40 --specular-spp 8)
"$GTBAKE" sweep --scenes "$SCENES" "${sweep[@]}" -q --out "$work/run/ref" >/dev/null

start=$(date +%s%N)
export SLURM_LOCAL_PORT=$((20000 + RANDOM % 20000))
eval "$("$CLUSTER_SCRIPTS/slurm-localhost.sh" start "$work/slurm")"
cleanup_hooks+=("\"$CLUSTER_SCRIPTS/slurm-localhost.sh\" stop \"$work/slurm\"")
echo "slurm up in $(seconds_since "$start") s (SLURM_CONF=$SLURM_CONF)"
# One CPU per task, so the 4 shards run two at a time on 2 cores.
GTBAKE_SBATCH_ARGS="--cpus-per-task=1" "$CLUSTER_SCRIPTS/submit.sh" 4 "$work/run" "$SCENES" -- \
  "${sweep[@]}"
read -r array merge <"$work/run/jobs"
state=""
for _ in $(seq 600); do
  state=$(scontrol show job "$merge" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | cut -d= -f2)
  [[ $state == COMPLETED || $state == FAILED || $state == CANCELLED || $state == TIMEOUT ]] && break
  [[ $(scontrol show job "$merge" 2>/dev/null) == *DependencyNeverSatisfied* ]] && break
  sleep 0.2
done
echo "slurm: array $array and merge $merge done in $(seconds_since "$start") s ($state)"
if [[ $state != COMPLETED ]]; then
  tail -n 5 "$work/run/logs"/* >&2 || true
  fail "merge job ended $state"
fi
for i in 0 1 2 3; do
  grep -q "shard $i/4: " "$work/run/logs/gtbake-sweep-${array}_$i.log" || fail "no log of shard $i"
done
grep -q "merge: 4 shards of 4" "$work/run/logs/gtbake-merge-$merge.log" || fail "no merge log"
same_sweep "$work/run/ref" "$work/run/sweep"
echo "PASS"
