#!/usr/bin/env bash
# 4 shards of the seven scenes (every channel, edge tiles) merged in any order equal the
# unsharded sweep byte for byte; merge refuses what it must, writing nothing.
source "$(dirname "$0")/common.sh"
args=(--scenes "$SCENES" --spp 16 --res 72x40 --specular-spp 8 -q)
"$GTBAKE" sweep "${args[@]}" --out "$work/one" >/dev/null
for i in 0 1 2 3; do
  "$GTBAKE" sweep "${args[@]}" --out "$work/s$i" --shard "$i/4" --threads $((1 + i % 2)) >/dev/null
done
"$GTBAKE" merge --out "$work/merged" "$work/s2" "$work/s0" "$work/s3" "$work/s1" >"$work/merge.log"
head -1 "$work/merge.log"
grep -q "merge: 4 shards of 4" "$work/merge.log" || fail "merge did not say what it combined"
same_sweep "$work/one" "$work/merged"

# Another partition (3 shards) of the same sweep gives the same bytes too.
for i in 0 1 2; do "$GTBAKE" sweep "${args[@]}" --out "$work/t$i" --shard "$i/3" >/dev/null; done
"$GTBAKE" merge --out "$work/merged3" "$work/t0" "$work/t1" "$work/t2" >/dev/null
same_sweep "$work/one" "$work/merged3"

refuses "missing tiles" "$work/r" merge --out "$work/r" "$work/s0" "$work/s1" "$work/s2"
refuses "overlapping shards" "$work/r" merge --out "$work/r" "$work/s0" "$work/s1" "$work/s1" \
  "$work/s2" "$work/s3"
refuses "different partitions" "$work/r" merge --out "$work/r" "$work/s0" "$work/t1"
"$GTBAKE" sweep "${args[@]}" --out "$work/seed2" --shard 3/4 --seed 2 >/dev/null
refuses "differ in seed 1 vs 2" "$work/r" merge --out "$work/r" "$work/s0" "$work/s1" \
  "$work/s2" "$work/seed2"
mkdir "$work/scenes2"
cp "$SCENES"/* "$work/scenes2/"
sed -i 's/"generator": "gtbake/"generator": "edited gtbake/' "$work/scenes2/wells.gltf"
"$GTBAKE" sweep "${args[@]/$SCENES/$work/scenes2}" --out "$work/edited" --shard 3/4 >/dev/null
refuses "contents of scene wells" "$work/r" merge --out "$work/r" "$work/s0" "$work/s1" \
  "$work/s2" "$work/edited"
cp -r "$work/s2" "$work/corrupt"
tile=$(ls "$work/corrupt/sweep-tiles/"*.tile | head -1)
printf '\x01' | dd of="$tile" bs=1 seek=$(($(stat -c %s "$tile") - 7)) conv=notrunc status=none
refuses "corrupt" "$work/r" merge --out "$work/r" "$work/s0" "$work/s1" "$work/corrupt" "$work/s3"
cp -r "$work/s3" "$work/unfinished"
rm "$work/unfinished/shard.manifest.json"
refuses "did not finish" "$work/r" merge --out "$work/r" "$work/s0" "$work/s1" "$work/s2" \
  "$work/unfinished"
echo "PASS"
