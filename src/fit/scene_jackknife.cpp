#include "fit/scene_jackknife.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "common/error.h"
#include "common/text_format.h"

namespace gtbake {

namespace {

// Where the band vanishes to rounding, constants are not scored: a ratio to a rounding error says
// nothing (units of G).
constexpr double kBandFloor = 1e-9;

template <typename Band>
GridPoint bandMax(const BandRule& rule, Band&& band_at) {
  GridPoint best;
  forEachBandPoint(rule, [&](double A, double rho) {
    const double band = band_at(A, rho);
    if (band > best.value) best = {band, A, rho};
  });
  return best;
}

}  // namespace

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
    forEachBandPoint(
        jk.rule, [&](double A, double rho) { curve.push_back(evalMultiBounce(r.linear, A, rho)); });
    out.push_back(std::move(curve));
  }
  return out;
}

namespace {

Grouping groupBy(const SweepData& data, const std::string& unit, std::string SweepScene::*field) {
  Grouping g;
  g.unit = unit;
  for (const SweepScene& view : data.scenes) {
    const std::string& name = (view.*field).empty() ? view.name : view.*field;
    const auto found = std::find(g.names.begin(), g.names.end(), name);
    g.of.push_back(static_cast<std::size_t>(found - g.names.begin()));
    if (found == g.names.end()) g.names.push_back(name);
  }
  return g;
}

// The refits without each group into out.leave_one_out; false (and out.message) when one of them
// is not determined by the rest.
bool leaveOneGroupOut(const SweepData& data, const MultiBounceFit& fit,
                      const MultiBounceCoeffs& shipped, const Grouping& groups,
                      SceneJackknife& out) {
  const std::size_t S = groups.names.size();
  out.leave_one_out.resize(S);
  // A replica the remaining groups cannot determine (e.g. one scene of a few distinct A left) is
  // no error of the fit: the jackknife is then unavailable, and says which group it was.
  std::vector<char> undetermined(S, 0);
  tbb::parallel_for(std::size_t{0}, S, [&](std::size_t c) {
    std::vector<bool> include(data.scenes.size(), true);
    for (std::size_t v = 0; v < include.size(); ++v) include[v] = groups.of[v] != c;
    try {
      const MultiBounceCoeffs k = coefficientsFromStatistics(sumScenes(fit.scene_stats, include),
                                                             data.albedos, fit.settings);
      out.leave_one_out[c] = {groups.names[c], k, maxCurveDifference(k, fit.linear.coeffs),
                              maxCurveDifference(k, shipped)};
    } catch (const Error&) {
      undetermined[c] = 1;
    }
  });
  for (std::size_t c = 0; c < S; ++c) {
    if (undetermined[c] == 0) continue;
    out.leave_one_out.clear();
    out.message = "the refit without " + groups.unit + " '" + groups.names[c] +
                  "' is not determined by the others (rank-deficient), so there is no " +
                  groups.unit + "-level SE, band or verdict (only the Monte Carlo SE)";
    return false;
  }
  return true;
}

// The jackknife covariance, SEs and correlation of the leave-one-out refits.
void jackknifeCovariance(SceneJackknife& out) {
  const double S = static_cast<double>(out.leave_one_out.size());
  out.covariance.fill(0.0);
  MultiBounceCoeffs mean{};
  for (const LeaveOneOut& r : out.leave_one_out) {
    for (int i = 0; i < 6; ++i) mean[i] += r.linear[i] / S;
  }
  const double scale = (S - 1.0) / S;
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
}

}  // namespace

Grouping groupByScene(const SweepData& data) {
  return groupBy(data, "scene", &SweepScene::cluster);
}

Grouping groupByType(const SweepData& data) {
  return groupBy(data, "type", &SweepScene::type);
}

SceneJackknife sceneJackknife(const SweepData& data, const MultiBounceFit& fit,
                              const MultiBounceCoeffs& shipped, const BandRule& rule) {
  return groupJackknife(data, fit, shipped, groupByScene(data), rule);
}

SceneJackknife typeJackknife(const SweepData& data, const MultiBounceFit& fit,
                             const MultiBounceCoeffs& shipped, const BandRule& rule) {
  return groupJackknife(data, fit, shipped, groupByType(data), rule);
}

SceneJackknife groupJackknife(const SweepData& data, const MultiBounceFit& fit,
                              const MultiBounceCoeffs& shipped, const Grouping& groups,
                              const BandRule& rule) {
  SceneJackknife out;
  const std::size_t S = groups.names.size();
  out.scenes = S;
  out.unit = groups.unit;
  out.rule = rule;
  out.mc_band_max = bandMax(
      rule, [&](double A, double rho) { return curveBand(fit.linear.mc_covariance, A, rho); });
  if (S >= 2 && !leaveOneGroupOut(data, fit, shipped, groups, out)) return out;
  if (S < kMinJackknifeScenes) {
    out.message = groups.unit + "-level uncertainty needs at least " +
                  std::to_string(kMinJackknifeScenes) + " " + groups.unit + "s; this sweep has " +
                  std::to_string(S) +
                  ", so there is no jackknife SE, band or verdict (only the Monte Carlo SE)";
    return out;
  }
  completeJackknife(out);
  // One simulation gives the thresholds over the whole grid and per range of A.
  std::vector<int> range_of;
  std::size_t j = 0;
  forEachBandPoint(rule, [&](double A, double) {
    range_of.push_back(out.scored[j++] != 0 ? static_cast<int>(rangeOf(rule, A)) : -1);
  });
  const std::size_t ranges = rule.ranges.size() - 1;
  const std::vector<double> by_range =
      simulatedGroupMaxT(bandReplicates(out), S, range_of, ranges, rule.max_t);
  const std::vector<double> maxima = overallMaxima(by_range, ranges);
  out.threshold = maxTQuantile(maxima, rule.max_t.level);
  out.range_thresholds = jointGroupThresholds(by_range, ranges, rule.max_t.level);
  out.pointwise_threshold = studentT975(S - 1);
  out.pointwise_false_alarm = maxTExceedance(maxima, out.pointwise_threshold);
  return out;
}

void completeJackknife(SceneJackknife& jk) {
  jk.available = true;
  jackknifeCovariance(jk);
  jk.band_max = bandMax(jk.rule, [&](double A, double rho) { return jackknifeBand(jk, A, rho); });
  jk.scored.clear();
  forEachBandPoint(jk.rule, [&](double A, double rho) {
    jk.scored.push_back(A < 1.0 && jackknifeBand(jk, A, rho) > kBandFloor ? 1 : 0);
  });
}

std::size_t rangeOf(const BandRule& rule, double A) {
  std::size_t r = 0;
  while (r + 2 < rule.ranges.size() && A >= rule.ranges[r + 1]) ++r;
  return r;
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
  forEachBandPoint(jackknife.rule, [&](double A, double rho) {
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
  const std::string where = "A = " + formatNumber(score.max_ratio.A, "%.3f") +
                            ", rho = " + formatNumber(score.max_ratio.rho, "%.2f");
  score.verdict =
      score.consistent
          ? "consistent with the path-traced data at the scene-mix uncertainty: max |dG|/band " +
                formatNumber(score.max_ratio.value, "%.2f") + " <= " + formatNumber(c, "%.2f") +
                " (simultaneous max-t; at " + where + ")"
          : "outside the scene-mix uncertainty at " + where + ", by " +
                formatNumber(score.max_ratio.value, "%.2f") +
                " band widths (simultaneous max-t threshold " + formatNumber(c, "%.2f") + ")";
  return score;
}

}  // namespace gtbake
