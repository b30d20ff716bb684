#!/bin/sh
# compare_fit.sh: CPU seconds (user + sys, /usr/bin/time) of `gtbake fit` for a baseline binary and
# a candidate on the same sweep, interleaved, median of RUNS, and their ratio. CPU time rather than
# wall time because the development machine is shared.
#
#   bench/fit/compare_fit.sh BASELINE_GTBAKE CANDIDATE_GTBAKE [SWEEP_DIR] [RUNS]
set -eu
base=$1
cand=$2
sweep=${3:-luts}
runs=${4:-3}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cpu() { # binary -> CPU seconds of one fit
  /usr/bin/time -f "%U %S" -o "$out/t" "$1" -q fit --sweep "$sweep" --out "$out/fit.json" >/dev/null
  awk '{ printf "%.3f\n", $1 + $2 }' "$out/t"
}
median() { sort -n | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
: >"$out/base"
: >"$out/cand"
i=0
while [ "$i" -lt "$runs" ]; do
  cpu "$base" >>"$out/base"
  cpu "$cand" >>"$out/cand"
  i=$((i + 1))
done
b=$(median <"$out/base")
c=$(median <"$out/cand")
echo "gtbake fit on $sweep, median CPU seconds of $runs runs: baseline $b, candidate $c," \
  "ratio $(awk -v b="$b" -v c="$c" 'BEGIN { printf "%.1f", b / c }')x"
