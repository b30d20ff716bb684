#include "fit/fit_errors.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/error.h"
#include "common/text_format.h"

namespace gtbake {

namespace {

// Grid of the curve-distance search (nodes; 1/200 in A and 1/200 of the ρ range).
constexpr int kGridSteps = 200;
// Local refinement: each round scans kRefineSteps² cells of a window around the best node and
// shrinks it by kRefineShrink (30 rounds: the window ends ~1e-9 of a grid cell wide).
constexpr int kRefineSteps = 10;
constexpr int kRefineRounds = 30;
constexpr double kRefineShrink = 0.5;

struct Accumulator {
  double sum2 = 0.0;
  double max_abs = 0.0;
  std::size_t count = 0;
  void add(double e) {
    sum2 += e * e;
    max_abs = std::max(max_abs, std::abs(e));
    ++count;
  }
  ErrorRow row(std::string label, double rho = 0.0) const {
    return {std::move(label), rho, count ? std::sqrt(sum2 / static_cast<double>(count)) : 0.0,
            max_abs};
  }
};

}  // namespace

void requireFiniteCoeffs(const MultiBounceCoeffs& coeffs, const std::string& what) {
  for (int i = 0; i < 6; ++i) {
    if (!std::isfinite(coeffs[i])) {
      throw Error(what + ": coefficient " + kCoeffNames[i] + " is not finite");
    }
  }
}

ErrorTable errorTable(const SweepData& data, const MultiBounceCoeffs& coeffs) {
  return errorTable(data, std::vector<MultiBounceCoeffs>(data.scenes.size(), coeffs));
}

ErrorTable errorTable(const SweepData& data, const std::vector<MultiBounceCoeffs>& per_view) {
  if (per_view.size() != data.scenes.size()) {
    throw Error("internal: error table with " + std::to_string(per_view.size()) +
                " sets of constants for " + std::to_string(data.scenes.size()) + " views");
  }
  ErrorTable table;
  Accumulator total;
  std::vector<Accumulator> scenes(data.scenes.size());
  for (std::size_t j = 0; j < data.albedos.size(); ++j) {
    Accumulator albedo;
    for (std::size_t s = 0; s < data.scenes.size(); ++s) {
      const Cubic theta = cubicAt(per_view[s], data.albedos[j]);
      for (std::size_t i = data.scenes[s].begin; i < data.scenes[s].end; ++i) {
        const double e = data.full.G[j][i] - evalCubic(theta, data.full.A[i]);
        albedo.add(e);
        scenes[s].add(e);
        total.add(e);
      }
    }
    table.per_albedo.push_back(albedo.row(formatNumber(data.albedos[j], "%.2f"), data.albedos[j]));
  }
  for (std::size_t s = 0; s < data.scenes.size(); ++s) {
    table.per_scene.push_back(scenes[s].row(data.scenes[s].name));
  }
  table.rmse = total.row("").rmse;
  table.max_abs = total.max_abs;
  return table;
}

CurveDifference maxCurveDifference(const MultiBounceCoeffs& k1, const MultiBounceCoeffs& k2) {
  MultiBounceCoeffs d;
  for (int i = 0; i < 6; ++i) d[i] = k1[i] - k2[i];
  const auto diff = [&](double A, double rho) { return evalMultiBounce(d, A, rho); };
  CurveDifference best;
  const auto scan = [&](double a_lo, double a_hi, double r_lo, double r_hi, int steps) {
    for (int u = 0; u <= steps; ++u) {
      const double A = a_lo + (a_hi - a_lo) * u / steps;
      for (int v = 0; v <= steps; ++v) {
        const double rho = r_lo + (r_hi - r_lo) * v / steps;
        const double value = diff(A, rho);
        if (std::abs(value) > best.value) best = {std::abs(value), A, rho, value};
      }
    }
  };
  scan(0.0, 1.0, kRhoMin, kRhoMax, kGridSteps);
  double half_a = 1.0 / kGridSteps;
  double half_r = (kRhoMax - kRhoMin) / kGridSteps;
  for (int round = 0; round < kRefineRounds; ++round) {
    const double A = best.A;
    const double rho = best.rho;
    scan(std::max(0.0, A - half_a), std::min(1.0, A + half_a), std::max(kRhoMin, rho - half_r),
         std::min(kRhoMax, rho + half_r), kRefineSteps);
    half_a *= kRefineShrink;
    half_r *= kRefineShrink;
  }
  return best;
}

}  // namespace gtbake
