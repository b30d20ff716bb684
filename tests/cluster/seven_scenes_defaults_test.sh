#!/usr/bin/env bash
# The default sweep of the seven scenes (gtbake sweep's defaults, every channel) from 4 shards,
# merged, equals the unsharded default sweep byte for byte.
source "$(dirname "$0")/common.sh"
start=$(date +%s%N)
"$GTBAKE" sweep --scenes "$SCENES" -q --out "$work/one" >/dev/null
for i in 0 1 2 3; do
  "$GTBAKE" sweep --scenes "$SCENES" -q --out "$work/s$i" --shard "$i/4"
done
"$GTBAKE" merge --out "$work/merged" "$work"/s? >"$work/merge.log"
head -1 "$work/merge.log"
same_sweep "$work/one" "$work/merged"
echo "PASS ($(seconds_since "$start") s)"
