#include "fit/fit_errors.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/error.h"
#include "fit/multibounce_fit.h"

namespace gtbake {

namespace {

constexpr double kRhoMin = 0.1;  // the paper's albedo range (SPEC §1.3), unitless
constexpr double kRhoMax = 0.9;
// Grid of the curve-distance search (nodes; 1/200 in A and 1/200 of the ρ range).
constexpr int kGridSteps = 200;
// Local refinement: each round shrinks the window around the best node by this factor.
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

std::string rhoLabel(double rho) {
  char text[16];
  std::snprintf(text, sizeof(text), "%.2f", rho);
  return text;
}

}  // namespace

void requireFiniteCoeffs(const MultiBounceCoeffs& coeffs, const std::string& what) {
  const char* names[6] = {"a1", "a0", "b1", "b0", "c1", "c0"};
  for (int i = 0; i < 6; ++i) {
    if (!std::isfinite(coeffs[i]))
      throw Error(what + ": coefficient " + names[i] + " is not finite");
  }
}

ErrorTable errorTable(const SweepData& data, const MultiBounceCoeffs& coeffs) {
  ErrorTable table;
  Accumulator total;
  std::vector<Accumulator> scenes(data.scenes.size());
  for (std::size_t j = 0; j < data.albedos.size(); ++j) {
    const Cubic theta = cubicAt(coeffs, data.albedos[j]);
    Accumulator albedo;
    for (std::size_t s = 0; s < data.scenes.size(); ++s) {
      for (std::size_t i = data.scenes[s].begin; i < data.scenes[s].end; ++i) {
        const double e = data.full.G[j][i] - evalCubic(theta, data.full.A[i]);
        albedo.add(e);
        scenes[s].add(e);
        total.add(e);
      }
    }
    table.per_albedo.push_back(albedo.row(rhoLabel(data.albedos[j]), data.albedos[j]));
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
  const auto scan = [&](double a_lo, double a_hi, double r_lo, double r_hi) {
    for (int u = 0; u <= kGridSteps; ++u) {
      const double A = a_lo + (a_hi - a_lo) * u / kGridSteps;
      for (int v = 0; v <= kGridSteps; ++v) {
        const double rho = r_lo + (r_hi - r_lo) * v / kGridSteps;
        const double value = diff(A, rho);
        if (std::abs(value) > best.value) best = {std::abs(value), A, rho, value};
      }
    }
  };
  scan(0.0, 1.0, kRhoMin, kRhoMax);
  double half_a = 1.0 / kGridSteps;
  double half_r = (kRhoMax - kRhoMin) / kGridSteps;
  for (int round = 0; round < kRefineRounds; ++round) {
    const double A = best.A;
    const double rho = best.rho;
    scan(std::max(0.0, A - half_a), std::min(1.0, A + half_a), std::max(kRhoMin, rho - half_r),
         std::min(kRhoMax, rho + half_r));
    half_a *= kRefineShrink;
    half_r *= kRefineShrink;
  }
  return best;
}

}  // namespace gtbake
