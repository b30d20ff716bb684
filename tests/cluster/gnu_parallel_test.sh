#!/usr/bin/env bash
# scripts/cluster/parallel-sweep.sh with this machine as the only host (":"): 4 shards under GNU
# parallel, two at a time, then the merge; equal to the unsharded sweep byte for byte.
source "$(dirname "$0")/common.sh"
command -v parallel >/dev/null || skip "GNU parallel is not installed (scripts/install-deps.sh)"
sweep=(--spp 16 --res 72x40 --specular-spp 8 --threads 1)
"$GTBAKE" sweep --scenes "$SCENES" "${sweep[@]}" -q --out "$work/run/ref" >/dev/null
start=$(date +%s%N)
GTBAKE_JOBS_PER_HOST=2 "$CLUSTER_SCRIPTS/parallel-sweep.sh" : 4 "$work/run" "$SCENES" -- \
  "${sweep[@]}" >"$work/parallel.log" 2>&1 || { cat "$work/parallel.log"; fail "parallel-sweep"; }
echo "parallel-sweep.sh: 4 shards + merge in $(seconds_since "$start") s"
grep -E "^shard [0-3]" "$work/parallel.log" | grep -q "shard.json" || fail "no shard summaries"
grep -q "merge: 4 shards of 4" "$work/parallel.log" || fail "no merge summary"
same_sweep "$work/run/ref" "$work/run/sweep"
echo "PASS"
