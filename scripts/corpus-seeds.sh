#!/usr/bin/env bash
# What another draw of the corpus would give (docs/scenes.md "Another draw of the corpus"): the
# scene-level figures of the Eq. 10 fit when the user's choice of scenes changes, not only the
# Monte Carlo seed. For each seed S the corpus is drawn again (`gtbake scenes --seed S`: every
# variant's parameters, clutter and terrain), swept at `gtbake all`'s corpus settings (128², 84
# walks) with Monte Carlo seed S, and fitted. Seed 1 is `gtbake all`'s own corpus and seed.
#
# Usage: scripts/corpus-seeds.sh OUT [GTBAKE] [SEED...]   (GTBAKE: build/gtbake; seeds: 1..8)
# Writes OUT/seed<S>/{scenes,sweep,fit.json} and OUT/summary.json (one record per seed: the
# verdict's detectable difference, the scene and type band maxima, how far the paper's constants
# lie outside the band, the refit's six coefficients; then min, mean, max and standard deviation
# over the seeds, also of the refit's curve G at the first seed's band maximum, beside that band).
# data/corpus_seeds/summary.json is the committed run of the default seeds; test
# Docs.CorpusSeedsSummaryMatchesLuts checks its seed-1 record against luts/fit/fit.json.
set -euo pipefail
out="${1:?usage: scripts/corpus-seeds.sh OUT [GTBAKE] [SEED...]}"
gtbake="${2:-build/gtbake}"
shift $(($# < 2 ? $# : 2))
seeds=("$@")
((${#seeds[@]})) || seeds=(1 2 3 4 5 6 7 8)
command -v jq >/dev/null || {
  echo "corpus-seeds: needs jq (scripts/install-deps.sh all)" >&2
  exit 2
}
records=()
for s in "${seeds[@]}"; do
  dir="$out/seed$s"
  echo "corpus-seeds: seed $s" >&2
  # The sweep gets the files in the corpus's order, type by type as `gtbake scenes` lists them
  # (the order `gtbake all` sweeps, so the fit sums the scenes in the same order).
  mapfile -t files < <("$gtbake" scenes --quiet --seed "$s" --out "$dir/scenes" | sed 's/.* -> //')
  "$gtbake" sweep --quiet --scenes "${files[@]}" --out "$dir/sweep" --res 128x128 --spp 84 \
    --seed "$s" --specular-roughness none >/dev/null
  "$gtbake" fit --quiet --sweep "$dir/sweep" --out "$dir/fit.json" >/dev/null
  records+=("$(jq -c --argjson seed "$s" '{
      seed: $seed,
      scenes: .scene_jackknife.n,
      types: .type_jackknife.n,
      detectable_difference: .shipped.against_band.detectable_difference.largest.value,
      scene_band_max: .scene_jackknife.band_max.value,
      type_band_max: .type_jackknife.band_max.value,
      paper_ratio_to_band: .shipped.against_band.max_ratio_to_band,
      paper_worst_point: {A: .shipped.against_band.worst_point.A,
        rho: .shipped.against_band.worst_point.rho},
      paper_max_curve_difference: .shipped.max_curve_difference.value,
      paper_max_curve_difference_at: {A: .shipped.max_curve_difference.A,
        rho: .shipped.max_curve_difference.rho},
      scene_band_max_at: {A: .scene_jackknife.band_max.A, rho: .scene_jackknife.band_max.rho},
      linear: .linear
    }' "$dir/fit.json")")
done
printf '%s\n' "${records[@]}" | jq -s --arg version "$("$gtbake" --version)" '
  def stats(f): [.[] | f] as $x | ($x | add / length) as $m
    | {min: ($x | min), mean: $m, max: ($x | max)}
      + if ($x | length) > 1
        then {sd: ([$x[] | (. - $m) * (. - $m)] | add / (($x | length) - 1) | sqrt)} else {} end;
  def curve($k; $A; $rho): (($k.a1 * $rho + $k.a0) * $A - ($k.b1 * $rho + $k.b0)) * $A * $A
    + ($k.c1 * $rho + $k.c0) * $A;
  .[0].scene_band_max_at as $p
  | {
    generator: ("scripts/corpus-seeds.sh, " + $version),
    settings: "gtbake scenes --seed S; gtbake sweep --res 128x128 --spp 84 --seed S --specular-roughness none; gtbake fit (defaults)",
    seeds: .,
    detectable_difference: stats(.detectable_difference),
    scene_band_max: stats(.scene_band_max),
    type_band_max: stats(.type_band_max),
    paper_ratio_to_band: stats(.paper_ratio_to_band),
    paper_max_curve_difference: stats(.paper_max_curve_difference),
    linear: ([.[0].linear | keys[]] as $keys
      | [$keys[] as $k | {($k): stats(.linear[$k])}] | add),
    curve_at_first_band_max: ({A: $p.A, rho: $p.rho, first_scene_band: .[0].scene_band_max}
      + stats(curve(.linear; $p.A; $p.rho)))
  }' >"$out/summary.json.tmp"
mv "$out/summary.json.tmp" "$out/summary.json"
echo "corpus-seeds: wrote $out/summary.json" >&2
