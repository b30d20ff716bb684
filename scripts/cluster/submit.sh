#!/usr/bin/env bash
# Submits a sharded gtbake sweep to Slurm: a job array of SHARDS tasks (sweep.sbatch) and a
# merge job that waits for all of them (--dependency=afterok). Prints the two job ids.
#
#   scripts/cluster/submit.sh SHARDS OUT SCENES... [-- SWEEP_OPTIONS...]
#   e.g. scripts/cluster/submit.sh 16 /shared/run1 /shared/scenes -- --res 1920x1080 --spp 4096
#
# OUT and SCENES must be on a filesystem every node sees. GTBAKE (default: gtbake on PATH) is the
# binary; GTBAKE_SBATCH_ARGS are extra sbatch options for both jobs (e.g. "--partition=render");
# SBATCH_* variables work as usual.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if (($# < 3)); then
  echo "usage: $0 SHARDS OUT SCENES... [-- SWEEP_OPTIONS...]" >&2
  exit 2
fi
shards=$1
out=$(mkdir -p "$2" && cd "$2" && pwd)
shift 2
scenes=()
while (($# > 0)) && [[ $1 != -- ]]; do
  scenes+=("$(realpath "$1")")
  shift
done
[[ ${1:-} == -- ]] && shift
[[ $shards =~ ^[1-9][0-9]*$ ]] || { echo "submit: SHARDS must be a positive count" >&2; exit 2; }
export GTBAKE_OUT=$out GTBAKE_SCENES="${scenes[*]}" GTBAKE_SWEEP_ARGS="$*"
if [[ -n ${GTBAKE:-} ]]; then GTBAKE=$(realpath "$GTBAKE"); export GTBAKE; fi
mkdir -p "$out/logs"
read -r -a sbatch_args <<<"${GTBAKE_SBATCH_ARGS:-}"
array=$(sbatch --parsable "${sbatch_args[@]}" --array="0-$((shards - 1))" \
  --output="$out/logs/%x-%A_%a.log" "$here/sweep.sbatch")
array=${array%%;*}
merge=$(sbatch --parsable "${sbatch_args[@]}" --dependency="afterok:$array" \
  --output="$out/logs/%x-%j.log" "$here/merge.sbatch")
merge=${merge%%;*}
echo "array job $array: $shards shards -> $out/shard-*; merge job $merge -> $out/sweep"
echo "$array $merge" >"$out/jobs"
