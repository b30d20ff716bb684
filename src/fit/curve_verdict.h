// The verdict on a set of Eq. 10 constants, range by range of A (docs/fit.md §5, "The verdict by
// range of A").
//
// One maximum of |G_k − G_refit| / SE_G over the whole (A, ρ) grid is dominated by A → 1, where
// every scene's open pixels pin the curve and the band shrinks to ~1e-4: it tests G(1, ρ) = 1 and
// barely sees an error where most pixels are. So the grid is split into ranges of A
// (BandRule::ranges, default [0, 0.3), [0.3, 0.7), [0.7, 1]) and each range gets
//   - its largest |ΔG| (ΔG = G_k − G_refit) and where;
//   - its largest |ΔG| / SE_G against its own threshold c_r. The thresholds are simultaneous
//     over the ranges and over every point of each (SceneJackknife::range_thresholds): when the
//     constants equal the population curve, some range is declared outside at most 5 % of the
//     time;
//   - its power: the detectable difference c_r · max SE_G over the range, the smallest |ΔG|
//     that the rule detects wherever in the range it sits;
//   - a verdict: outside (the largest ratio exceeds c_r), else "too few scenes to judge" when
//     the detectable difference exceeds the useful power (default 0.05 in G, or the tolerance
//     --fail-above), else consistent.
// A range whose largest ratio sits at A ≥ 0.95 (the open-surface limit, where every scene's open
// pixels pin G(1, ρ) = 1 and the band shrinks to ~1e-4) says so, with its largest ratio below
// A = 0.95: its verdict there tests G(1, ρ) = 1, not the range.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "fit/multibounce_coeffs.h"
#include "fit/scene_jackknife.h"

namespace gtbake {

enum class Verdict { kConsistent, kOutside, kTooFewScenes };
// "consistent", "outside", "too few scenes to judge".
const char* verdictName(Verdict verdict);

// A detectable difference above this (in G) is too little power to call a range consistent: a
// difference of 0.05 darkens a mid-grey pixel visibly.
inline constexpr double kUsefulPower = 0.05;
// From this A on, the band is pinned by open pixels (the open-surface limit).
inline constexpr double kOpenLimitA = 0.95;

struct VerdictRule {
  double useful_power = kUsefulPower;
  // A practical tolerance in G (--fail-above): a range fails only when it is outside and its
  // largest |ΔG| exceeds it; it also sets the power a range needs to be judged.
  std::optional<double> fail_above;
  double powerNeeded() const { return fail_above ? *fail_above : useful_power; }
};

struct RangeScore {
  double lo = 0.0, hi = 0.0;  // A in [lo, hi) ([lo, hi] for the last range)
  std::size_t scored_points = 0;
  GridPoint max_difference;        // max |ΔG| over the range's grid points, and where
  double signed_difference = 0.0;  // ΔG there
  GridPoint max_ratio;             // max |ΔG| / SE_G over its scored points, and where
  double ratio_difference = 0.0;   // ΔG there
  double ratio_band = 0.0;         // SE_G there
  double threshold = 0.0;          // c_r
  GridPoint detectable;            // max of c_r · SE_G over the scored points, and where
  double median_band = 0.0;        // median SE_G over the scored points
  bool near_open = false;          // max_ratio sits at A ≥ kOpenLimitA
  GridPoint max_ratio_away;        // max |ΔG| / SE_G over the scored points with A < kOpenLimitA
  bool detected = false;           // max_ratio > c_r
  bool fails = false;              // detected and beyond the tolerance (if any)
  Verdict verdict = Verdict::kTooFewScenes;
  // From the points (validate_data.h): the range's share of the pixels and the RMS of ΔG over
  // its pixels and the sweep's albedos.
  double pixel_share = 0.0;
  double pixel_rms_difference = 0.0;
  std::string text;  // one line: the verdict and why
};

struct CurveVerdict {
  bool available = false;
  std::string message;  // why not, when not available
  VerdictRule rule;
  std::vector<RangeScore> ranges;
  BandScore overall;  // the single maximum over the whole grid (worst point, global threshold)
  Verdict verdict = Verdict::kTooFewScenes;
  std::string headline;  // one line
};

// Range r of `v` as text: "[0.3, 0.7)", the last one closed ("[0.7, 1.0]").
std::string rangeLabel(const CurveVerdict& v, std::size_t r);

// Scores `given` against the band of `jk` around `refit`, range by range. Without a jackknife
// every range and the whole are "too few scenes to judge".
CurveVerdict judgeCurve(const SceneJackknife& jk, const MultiBounceCoeffs& refit,
                        const MultiBounceCoeffs& given, const VerdictRule& rule = {});

}  // namespace gtbake
