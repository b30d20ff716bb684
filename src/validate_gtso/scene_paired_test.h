// Paired scene-level tests: "X beats Y" only when the per-scene differences say so
// (docs/validate_gtso.md §2).
//
// Scenes, not pixels, are the independent units: pixels of one scene share its geometry, so a
// pixel-level test would call almost any difference significant. Given each scene's value of X
// and Y (e.g. RMSE), d_s = x_s − y_s, the test is the two-sided sign-flip permutation test of
// mean d = 0: under the null each d_s is as likely to carry either sign, so the p-value is the
// fraction of the 2^S sign patterns whose |mean| is at least the observed one (exact for
// S ≤ kExactSignFlipScenes, else kSignFlipDraws deterministic random patterns). The paired t
// statistic mean / (sd/√S) is reported beside it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace gtbake {

inline constexpr std::size_t kExactSignFlipScenes = 20;
inline constexpr std::size_t kSignFlipDraws = 1u << 20;
// The drawn patterns take 8 MB per 64 scenes, kept for the run.
inline constexpr std::size_t kMaxPairedScenes = 1024;
inline constexpr double kSignificance = 0.05;  // two-sided
inline constexpr const char* kPairedTestMethod =
    "two-sided sign-flip permutation test of the mean per-scene difference (exact over all 2^S "
    "sign patterns), scenes as units; significant at p < 0.05";

struct PairedTest {
  std::size_t scenes = 0;
  double mean_difference = 0.0;  // mean of x_s − y_s
  double t = 0.0;                // paired t statistic (0 when every d_s is equal)
  double p_value = 1.0;
  bool significant = false;  // p < kSignificance
};

// How many of `patterns` sign patterns give |Σ_s ±d_s| ≥ target, scene s negated when bit s % 64
// of the pattern's word s / 64 is set (bits at or past S = d.size() are ignored). Pattern k is the
// bits of k itself when `drawn` is null (the exact enumeration, S ≤ 64), else the (S + 63) / 64
// words at drawn[k · words]. The sum may differ from a scene-by-scene sum in its last bits, which
// the caller's target slack covers.
std::uint64_t signFlipCountAtLeast(const std::vector<double>& d, double target,
                                   const std::uint64_t* drawn, std::uint64_t patterns);

// Throws gtbake::Error when x and y differ in length or have fewer than 2 or more than
// kMaxPairedScenes scenes.
PairedTest pairedSignFlip(const std::vector<double>& x, const std::vector<double>& y);

// A method ranking at one roughness: `best` has the lowest pooled value; each other method is
// tested against it, and `tied` lists those not significantly worse.
struct RankingTest {
  std::string best;
  std::vector<std::string> others;  // in pooled order
  std::vector<PairedTest> vs_best;  // other − best
  std::vector<std::string> tied;
  std::string statement;  // one sentence generated from the above
};

// per_scene[method][scene] and pooled[method] for `names`; best = argmin pooled.
RankingTest rankingTest(const std::vector<std::string>& names,
                        const std::vector<std::vector<double>>& per_scene,
                        const std::vector<double>& pooled);

}  // namespace gtbake
