#include "fit/scene_jackknife.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/error.h"

namespace gtbake {

namespace {

// The band grid: A = k / kBandASteps, k = 1..kBandASteps (A = 0 is excluded: G = 0 there for
// every k, and |ΔG| / SE_G tends to a finite limit), ρ in kBandRhoSteps equal steps of
// [0.1, 0.9] (the paper's albedo range). Steps of 0.005 in A and 0.01 in ρ.
constexpr int kBandASteps = 200;
constexpr int kBandRhoSteps = 80;
// Where the band vanishes to rounding (G(1, ρ) = 1 for every replica under --constrain-open, so
// the replicas agree to ~1e-15), constants are not scored: a ratio to a rounding error says
// nothing (units of G).
constexpr double kBandFloor = 1e-9;

// Two-sided 95 % quantiles t_{0.975, ν} of Student's t for ν = 1..30 (standard tables).
// clang-format off
constexpr double kT975[30] = {
    12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
     2.201, 2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
     2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
// clang-format on

template <typename F>
void forEachGridPoint(F&& f) {
  for (int u = 1; u <= kBandASteps; ++u) {
    const double A = static_cast<double>(u) / kBandASteps;
    for (int v = 0; v <= kBandRhoSteps; ++v) {
      f(A, kRhoMin + (kRhoMax - kRhoMin) * v / kBandRhoSteps);
    }
  }
}

template <typename Band>
GridPoint bandMax(Band&& band_at) {
  GridPoint best;
  forEachGridPoint([&](double A, double rho) {
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

}  // namespace

Grouping groupByScene(const SweepData& data) {
  return groupBy(data, "scene", &SweepScene::cluster);
}

Grouping groupByType(const SweepData& data) {
  return groupBy(data, "type", &SweepScene::type);
}

SceneJackknife sceneJackknife(const SweepData& data, const MultiBounceFit& fit,
                              const MultiBounceCoeffs& shipped) {
  return groupJackknife(data, fit, shipped, groupByScene(data));
}

SceneJackknife typeJackknife(const SweepData& data, const MultiBounceFit& fit,
                             const MultiBounceCoeffs& shipped) {
  return groupJackknife(data, fit, shipped, groupByType(data));
}

SceneJackknife groupJackknife(const SweepData& data, const MultiBounceFit& fit,
                              const MultiBounceCoeffs& shipped, const Grouping& groups) {
  SceneJackknife out;
  const std::size_t S = groups.names.size();
  out.scenes = S;
  out.unit = groups.unit;
  out.mc_band_max =
      bandMax([&](double A, double rho) { return curveBand(fit.linear.mc_covariance, A, rho); });
  if (S >= 2) {
    out.leave_one_out.resize(S);
    // A replica the remaining scenes cannot determine (e.g. one scene of a few distinct A left) is
    // no error of the fit: the jackknife is then unavailable, and says which scene it was.
    std::vector<char> undetermined(S, 0);
    tbb::parallel_for(std::size_t{0}, S, [&](std::size_t s) {
      std::vector<bool> include(data.scenes.size(), true);
      for (std::size_t v = 0; v < include.size(); ++v) include[v] = groups.of[v] != s;
      try {
        const MultiBounceCoeffs k = coefficientsFromStatistics(sumScenes(fit.scene_stats, include),
                                                               data.albedos, fit.settings);
        out.leave_one_out[s] = {groups.names[s], k, maxCurveDifference(k, fit.linear.coeffs),
                                maxCurveDifference(k, shipped)};
      } catch (const Error&) {
        undetermined[s] = 1;
      }
    });
    for (std::size_t s = 0; s < S; ++s) {
      if (undetermined[s] == 0) continue;
      out.leave_one_out.clear();
      out.message = "the refit without " + groups.unit + " '" + groups.names[s] +
                    "' is not determined by the others (rank-deficient), so there is no " +
                    groups.unit + "-level SE, band or verdict (only the Monte Carlo SE)";
      return out;
    }
  }
  if (S < kMinJackknifeScenes) {
    out.message = groups.unit + "-level uncertainty needs at least " +
                  std::to_string(kMinJackknifeScenes) + " " + groups.unit + "s; this sweep has " +
                  std::to_string(S) +
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
  out.band_max = bandMax([&](double A, double rho) { return jackknifeBand(out, A, rho); });
  out.threshold = studentT975(S - 1);
  return out;
}

BandScore scoreAgainstBand(const SceneJackknife& jackknife, const MultiBounceCoeffs& refit,
                           const MultiBounceCoeffs& k) {
  BandScore score;
  if (!jackknife.available) {
    score.verdict = "not scored: " + jackknife.message;
    return score;
  }
  score.threshold = jackknife.threshold;
  forEachGridPoint([&](double A, double rho) {
    const double band = jackknifeBand(jackknife, A, rho);
    const double diff = evalMultiBounce(k, A, rho) - evalMultiBounce(refit, A, rho);
    const double ratio = std::abs(diff) / band;
    if (band > kBandFloor && ratio > score.max_ratio.value) {
      score.max_ratio = {ratio, A, rho};
      score.difference = diff;
      score.band = band;
    }
  });
  score.consistent = score.max_ratio.value <= score.threshold;
  const std::string where =
      "A = " + fixed(score.max_ratio.A, "%.3f") + ", rho = " + fixed(score.max_ratio.rho, "%.2f");
  score.verdict =
      score.consistent
          ? "consistent with the path-traced data at the scene-mix uncertainty: max |dG|/band " +
                fixed(score.max_ratio.value, "%.2f") + " <= " + fixed(score.threshold, "%.2f") +
                " (at " + where + ")"
          : "outside the scene-mix uncertainty at " + where + ", by " +
                fixed(score.max_ratio.value, "%.2f") + " band widths (threshold " +
                fixed(score.threshold, "%.2f") + ")";
  return score;
}

}  // namespace gtbake
