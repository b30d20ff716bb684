# Shared by the tests/cluster scripts (sourced). Environment from CTest: GTBAKE (the binary),
# SCENES (data/scenes), CLUSTER_SCRIPTS (scripts/cluster).
set -euo pipefail
: "${GTBAKE:?}" "${SCENES:?}" "${CLUSTER_SCRIPTS:?}"
work=$(mktemp -d "${TMPDIR:-/tmp}/gtbake-cluster-test.XXXXXX")
cleanup_hooks=()
cleanup() {
  for hook in "${cleanup_hooks[@]}"; do eval "$hook" || true; done
  rm -rf "$work"
}
trap cleanup EXIT

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

skip() {
  echo "SKIP: $*"
  exit 77
}

# same_sweep A B: every EXR and PNG byte-identical, the same file list, and sweep.json equal
# apart from the run statistics (timings, rates, thread count).
same_sweep() {
  local a=$1 b=$2
  local files_a files_b
  files_a=$(cd "$a" && ls ./*.exr ./*.png sweep.json sweep.manifest.json | sort)
  files_b=$(cd "$b" && ls ./*.exr ./*.png sweep.json sweep.manifest.json | sort)
  [[ $files_a == "$files_b" ]] || fail "$a and $b hold different files"
  local n=0
  for f in "$a"/*.exr "$a"/*.png; do
    cmp -s "$f" "$b/$(basename "$f")" || fail "$(basename "$f") differs between $a and $b"
    n=$((n + 1))
  done
  local timing='"(seconds|build_seconds|trace_seconds|rays_per_second|threads)":'
  diff <(grep -vE "$timing" "$a/sweep.json") <(grep -vE "$timing" "$b/sweep.json") >&2 ||
    fail "sweep.json differs beyond timings between $a and $b"
  echo "same bytes: $n EXR/PNG files, sweep.json apart from timings ($a = $b)"
}

# refuses "FRAGMENT" OUT_DIR gtbake-args...: exit 1, one line on stderr containing FRAGMENT, and
# OUT_DIR not created.
refuses() {
  local fragment=$1 out=$2
  shift 2
  local status=0
  "$GTBAKE" "$@" >"$work/refusal.out" 2>"$work/refusal.err" || status=$?
  ((status == 1)) || fail "expected exit 1 for '$fragment', got $status: $(cat "$work/refusal.err")"
  (($(wc -l <"$work/refusal.err") == 1)) || fail "not one line: $(cat "$work/refusal.err")"
  grep -qF -- "$fragment" "$work/refusal.err" || fail "no '$fragment' in: $(cat "$work/refusal.err")"
  [[ ! -e $out ]] || fail "$out was created by a refused merge"
  echo "refused ($fragment): $(cat "$work/refusal.err")"
}

# seconds_since START_NS: elapsed seconds since `date +%s%N` gave START_NS, e.g. "12.345".
seconds_since() {
  local ms=$((($(date +%s%N) - $1) / 1000000))
  printf '%d.%03d' $((ms / 1000)) $((ms % 1000))
}
