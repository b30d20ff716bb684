#!/usr/bin/env bash
# A sweep stopped by SIGTERM (and one killed by SIGKILL) mid-way and resumed writes the bytes of
# an uninterrupted sweep; a stopped or killed run never leaves a partial output in place of a
# good one.
source "$(dirname "$0")/common.sh"
args=(--scenes "$SCENES/terrain.gltf" "$SCENES/cavity.gltf" "$SCENES/wells.gltf" --spp 48
  --res 128x96 --specular-spp 8 --threads 2)
tiles_total=36 # 3 scenes × 4 × 3 tiles of 32²
"$GTBAKE" sweep "${args[@]}" -q --out "$work/ref" >/dev/null

# Starts a sweep into $1 (extra arguments after it), waits until it has saved 4 tiles, sends $2.
interrupt() {
  local out=$1 signal=$2
  shift 2
  "$GTBAKE" sweep "${args[@]}" "$@" --out "$out" >"$work/run.out" 2>"$work/run.err" &
  local pid=$!
  for _ in $(seq 600); do
    (($(ls "$out/sweep-tiles/" 2>/dev/null | grep -c '\.tile$') >= 4)) && break
    sleep 0.05
  done
  kill "-$signal" "$pid"
  local status=0
  wait "$pid" || status=$?
  echo "$status"
}

status=$(interrupt "$work/term" TERM)
((status == 143)) || fail "SIGTERM: exit $status, expected 143: $(tail -1 "$work/run.err")"
grep -q "interrupted by SIGTERM: .* tiles are saved in .*; to resume, run again: gtbake sweep" \
  "$work/run.err" || fail "SIGTERM: no resume instructions: $(tail -1 "$work/run.err")"
tail -1 "$work/run.err"
[[ ! -e $work/term/sweep.json && -z $(ls "$work/term"/*.exr 2>/dev/null) ]] ||
  fail "SIGTERM: outputs written by an interrupted sweep"
saved=$(ls "$work/term/sweep-tiles" | grep -c '\.tile$')
((saved >= 4 && saved < tiles_total)) || fail "SIGTERM: $saved tiles saved, expected mid-way"
"$GTBAKE" sweep "${args[@]}" --out "$work/term" --resume >/dev/null 2>"$work/resume.err"
grep -q "resumed: $saved of $tiles_total tiles" "$work/resume.err" ||
  fail "resume did not reuse the $saved saved tiles: $(cat "$work/resume.err")"
[[ ! -e $work/term/sweep-tiles ]] || fail "checkpoints left after a finished sweep"
same_sweep "$work/ref" "$work/term"

status=$(interrupt "$work/kill" KILL)
((status == 137)) || fail "SIGKILL: exit $status, expected 137"
saved=$(ls "$work/kill/sweep-tiles" | grep -c '\.tile$')
echo "SIGKILL after $saved tiles"
"$GTBAKE" sweep "${args[@]}" -q --out "$work/kill" >/dev/null # the same command again
same_sweep "$work/ref" "$work/kill"

# A good sweep stays in place, byte for byte, when another sweep into its directory is killed;
# that sweep's tiles are then refused by --resume of the first one's command, and replaced by it
# without --resume.
cp -r "$work/ref" "$work/good"
status=$(interrupt "$work/good" KILL --seed 2)
((status == 137)) || fail "SIGKILL (seed 2): exit $status"
same_sweep "$work/ref" "$work/good"
status=0
"$GTBAKE" sweep "${args[@]}" -q --out "$work/good" --resume 2>"$work/err" >/dev/null || status=$?
((status == 1)) && grep -q "holds tiles of another sweep" "$work/err" ||
  fail "--resume accepted another sweep's tiles: $(cat "$work/err")"
"$GTBAKE" sweep "${args[@]}" --out "$work/good" >/dev/null 2>"$work/err"
grep -q "removing the tiles of another sweep" "$work/err" || fail "stale tiles not reported"
same_sweep "$work/ref" "$work/good"
echo "PASS"
