#include "fit/scene_jackknife.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "common/error.h"

namespace gtbake {

namespace {

// Where the band vanishes to rounding, constants are not scored: a ratio to a rounding error says
// nothing (units of G).
constexpr double kBandFloor = 1e-9;

// Two-sided 95 % quantiles t_{0.975, ν} of Student's t for ν = 1..30 (standard tables).
// clang-format off
constexpr double kT975[30] = {
    12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
     2.201, 2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
     2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
// clang-format on

// Calls f(A, ρ) on the grid of `rule`, A slowest, ρ fastest (A = 0 is excluded: G = 0 there for
// every k, and |ΔG| / SE_G tends to a finite limit).
template <typename F>
void forEachGridPoint(const BandRule& rule, F&& f) {
  for (int u = 1; u <= rule.a_steps; ++u) {
    const double A = static_cast<double>(u) / rule.a_steps;
    for (int v = 0; v <= rule.rho_steps; ++v) {
      f(A, kRhoMin + (kRhoMax - kRhoMin) * v / rule.rho_steps);
    }
  }
}

template <typename Band>
GridPoint bandMax(const BandRule& rule, Band&& band_at) {
  GridPoint best;
  forEachGridPoint(rule, [&](double A, double rho) {
    const double band = band_at(A, rho);
    if (band > best.value) best = {band, A, rho};
  });
  return best;
}

std::string fixed(double v, const char* format) {
  char text[32];
  std::snprintf(text, sizeof(text), format, v);
  return text;
}

}  // namespace

double studentT975(std::size_t dof) {
  return dof >= 1 && dof <= 30 ? kT975[dof - 1] : 1.96;
}

double curveBand(const std::array<double, 36>& covariance, double A, double rho) {
  const MultiBounceCoeffs g = multiBounceGradient(A, rho);
  double var = 0.0;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) var += g[r] * covariance[6 * r + c] * g[c];
  }
  return std::sqrt(std::max(var, 0.0));
}

double jackknifeBand(const SceneJackknife& jk, double A, double rho) {
  const double S = static_cast<double>(jk.leave_one_out.size());
  double mean = 0.0;
  for (const LeaveOneOut& r : jk.leave_one_out) mean += evalMultiBounce(r.linear, A, rho) / S;
  double sum2 = 0.0;
  for (const LeaveOneOut& r : jk.leave_one_out) {
    const double d = evalMultiBounce(r.linear, A, rho) - mean;
    sum2 += d * d;
  }
  return std::sqrt((S - 1.0) / S * sum2);
}

ReplicateMatrix bandReplicates(const SceneJackknife& jk) {
  ReplicateMatrix out;
  for (const LeaveOneOut& r : jk.leave_one_out) {
    std::vector<double> curve;
    forEachGridPoint(
        jk.rule, [&](double A, double rho) { curve.push_back(evalMultiBounce(r.linear, A, rho)); });
    out.push_back(std::move(curve));
  }
  return out;
}

namespace {

// The clusters of the sweep's entries (views of one scene are one cluster), in order of first
// appearance, and each entry's cluster index.
std::vector<std::string> clustersOf(const SweepData& data, std::vector<std::size_t>& index) {
  std::vector<std::string> names;
  for (const SweepScene& scene : data.scenes) {
    const auto it = std::find(names.begin(), names.end(), scene.clusterName());
    index.push_back(static_cast<std::size_t>(it - names.begin()));
    if (it == names.end()) names.push_back(scene.clusterName());
  }
  return names;
}

// The refits without each cluster into out.leave_one_out; false (and out.message) when one of
// them is not determined by the rest.
bool leaveOneClusterOut(const SweepData& data, const MultiBounceFit& fit,
                        const MultiBounceCoeffs& shipped, SceneJackknife& out) {
  std::vector<std::size_t> cluster_of;
  const std::vector<std::string> clusters = clustersOf(data, cluster_of);
  const std::size_t S = clusters.size();
  out.leave_one_out.resize(S);
  // A replica the remaining scenes cannot determine (e.g. one scene of a few distinct A left) is
  // no error of the fit: the jackknife is then unavailable, and says which scene it was.
  std::vector<char> undetermined(S, 0);
  tbb::parallel_for(std::size_t{0}, S, [&](std::size_t c) {
    std::vector<bool> include(data.scenes.size(), true);
    for (std::size_t s = 0; s < include.size(); ++s) include[s] = cluster_of[s] != c;
    try {
      const MultiBounceCoeffs k = coefficientsFromStatistics(sumScenes(fit.scene_stats, include),
                                                             data.albedos, fit.settings);
      out.leave_one_out[c] = {clusters[c], k, maxCurveDifference(k, fit.linear.coeffs),
                              maxCurveDifference(k, shipped)};
    } catch (const Error&) {
      undetermined[c] = 1;
    }
  });
  for (std::size_t c = 0; c < S; ++c) {
    if (undetermined[c] == 0) continue;
    out.leave_one_out.clear();
    out.message = "the refit without scene '" + clusters[c] +
                  "' is not determined by the other scenes (rank-deficient), so there is no "
                  "scene-level SE, band or verdict (only the Monte Carlo SE)";
    return false;
  }
  return true;
}

}  // namespace

SceneJackknife sceneJackknife(const SweepData& data, const MultiBounceFit& fit,
                              const MultiBounceCoeffs& shipped, const BandRule& rule) {
  SceneJackknife out;
  std::vector<std::size_t> cluster_of;
  const std::size_t S = clustersOf(data, cluster_of).size();
  out.scenes = S;
  out.rule = rule;
  out.mc_band_max = bandMax(
      rule, [&](double A, double rho) { return curveBand(fit.linear.mc_covariance, A, rho); });
  if (S >= 2 && !leaveOneClusterOut(data, fit, shipped, out)) return out;
  if (S < kMinJackknifeScenes) {
    out.message = "scene-level uncertainty needs at least " + std::to_string(kMinJackknifeScenes) +
                  " scenes; this sweep has " + std::to_string(S) +
                  ", so there is no jackknife SE, band or verdict (only the Monte Carlo SE)";
    return out;
  }
  out.available = true;
  MultiBounceCoeffs mean{};
  for (const LeaveOneOut& r : out.leave_one_out) {
    for (int i = 0; i < 6; ++i) mean[i] += r.linear[i] / static_cast<double>(S);
  }
  const double scale = static_cast<double>(S - 1) / static_cast<double>(S);
  for (const LeaveOneOut& r : out.leave_one_out) {
    for (int a = 0; a < 6; ++a) {
      for (int b = 0; b < 6; ++b) {
        out.covariance[6 * a + b] += scale * (r.linear[a] - mean[a]) * (r.linear[b] - mean[b]);
      }
    }
  }
  for (int a = 0; a < 6; ++a) out.se[a] = std::sqrt(out.covariance[6 * a + a]);
  for (int a = 0; a < 6; ++a) {
    for (int b = 0; b < 6; ++b) {
      out.correlation[6 * a + b] = out.covariance[6 * a + b] / (out.se[a] * out.se[b]);
    }
  }
  out.band_max = bandMax(rule, [&](double A, double rho) { return jackknifeBand(out, A, rho); });
  forEachGridPoint(rule, [&](double A, double rho) {
    out.scored.push_back(A < 1.0 && jackknifeBand(out, A, rho) > kBandFloor ? 1 : 0);
  });
  const std::vector<double> maxima = simulatedMaxT(bandReplicates(out), S, out.scored, rule.max_t);
  out.threshold = maxTQuantile(maxima, rule.max_t.level);
  out.pointwise_threshold = studentT975(S - 1);
  out.pointwise_false_alarm = maxTExceedance(maxima, out.pointwise_threshold);
  return out;
}

BandScore scoreAgainstBand(const SceneJackknife& jackknife, const MultiBounceCoeffs& refit,
                           const MultiBounceCoeffs& k) {
  BandScore score;
  if (!jackknife.available) {
    score.verdict = "not scored: " + jackknife.message;
    return score;
  }
  const double c = jackknife.threshold;
  score.threshold = c;
  score.pointwise_threshold = jackknife.pointwise_threshold;
  score.smallest_detectable.value = std::numeric_limits<double>::infinity();
  std::size_t j = 0;
  forEachGridPoint(jackknife.rule, [&](double A, double rho) {
    if (jackknife.scored[j++] == 0) {
      ++score.excluded_points;
      return;
    }
    ++score.scored_points;
    const double band = jackknifeBand(jackknife, A, rho);
    const double diff = evalMultiBounce(k, A, rho) - evalMultiBounce(refit, A, rho);
    const double ratio = std::abs(diff) / band;
    if (ratio > score.max_ratio.value) {
      score.max_ratio = {ratio, A, rho};
      score.difference = diff;
      score.band = band;
    }
    if (c * band < score.smallest_detectable.value) score.smallest_detectable = {c * band, A, rho};
    if (c * band > score.largest_undetectable.value)
      score.largest_undetectable = {c * band, A, rho};
  });
  score.consistent = score.max_ratio.value <= c;
  const std::string where =
      "A = " + fixed(score.max_ratio.A, "%.3f") + ", rho = " + fixed(score.max_ratio.rho, "%.2f");
  score.verdict =
      score.consistent
          ? "consistent with the path-traced data at the scene-mix uncertainty: max |dG|/band " +
                fixed(score.max_ratio.value, "%.2f") + " <= " + fixed(c, "%.2f") +
                " (simultaneous max-t; at " + where + ")"
          : "outside the scene-mix uncertainty at " + where + ", by " +
                fixed(score.max_ratio.value, "%.2f") +
                " band widths (simultaneous max-t threshold " + fixed(c, "%.2f") + ")";
  return score;
}

}  // namespace gtbake
