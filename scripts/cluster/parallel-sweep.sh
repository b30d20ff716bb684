#!/usr/bin/env bash
# A sharded gtbake sweep over SSH hosts with GNU parallel, then the merge on this machine
# (docs/cluster.md).
#
#   scripts/cluster/parallel-sweep.sh HOSTS SHARDS OUT SCENES... [-- SWEEP_OPTIONS...]
#
# HOSTS is a GNU parallel --sshloginfile (one "host" or "N/host" per line; ":" is this machine),
# or ":" alone to run every shard here. Each host runs one shard at a time (GTBAKE_JOBS_PER_HOST
# to change) with all its cores. OUT and SCENES must be at the same absolute paths on every host
# (a shared filesystem), and GTBAKE (default: gtbake on PATH) too. A shard that fails is retried
# once (GTBAKE_RETRIES) and resumes from its finished tiles.
set -euo pipefail
if (($# < 4)); then
  echo "usage: $0 HOSTS SHARDS OUT SCENES... [-- SWEEP_OPTIONS...]" >&2
  exit 2
fi
hosts=$1
shards=$2
out=$(mkdir -p "$3" && cd "$3" && pwd)
shift 3
scenes=()
while (($# > 0)) && [[ $1 != -- ]]; do
  scenes+=("$(realpath "$1")")
  shift
done
[[ ${1:-} == -- ]] && shift
[[ $shards =~ ^[1-9][0-9]*$ ]] || { echo "parallel-sweep: SHARDS must be a positive count" >&2; exit 2; }
gtbake=${GTBAKE:-gtbake}
[[ $gtbake == */* ]] && gtbake=$(realpath "$gtbake")
if [[ $hosts == : ]]; then
  login=(--sshlogin :)
else
  login=(--sshloginfile "$hosts")
fi
parallel --will-cite -q "${login[@]}" --jobs "${GTBAKE_JOBS_PER_HOST:-1}" \
  --retries "$((${GTBAKE_RETRIES:-1} + 1))" --halt now,fail=1 --line-buffer --tagstring 'shard {}' \
  "$gtbake" sweep --scenes "${scenes[@]}" --out "$out/shard-{}" --shard "{}/$shards" "$@" \
  ::: $(seq 0 $((shards - 1)))
shard_dirs=()
for ((i = 0; i < shards; ++i)); do shard_dirs+=("$out/shard-$i"); done
"$gtbake" merge --out "$out/sweep" "${shard_dirs[@]}"
