#include "fit/multibounce_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"
#include "fit/ceres_linear.h"
#include "fit/shape_constrained_fit.h"

namespace gtbake {

namespace {

// Points per blocked rank update of the sandwich's meat (a multiple of the SIMD width; large
// enough that the update runs as a matrix product).
constexpr std::size_t kSandwichBatch = 512;

CubicParameterization parameterization(const FitSettings& settings) {
  return settings.constrain_open ? openConstrainedCubic() : freeCubic();
}

// φ̂ of every level for one albedo; the unit covariance of level 0 when asked.
struct LevelSolves {
  std::array<Cubic, kLevels> theta{};
  std::vector<double> unit_covariance;  // (TᵀSwT)⁻¹, N × N, level 0
};

LevelSolves solveLevels(const LevelStatistics& sums, std::size_t albedo,
                        const CubicParameterization& p, bool with_covariance) {
  LevelSolves out;
  for (int l = 0; l < kLevels; ++l) {
    const ReducedProblem reduced = reduceProblem(sums[l], albedo, p);
    const LinearSolve solve =
        solveLinear(reduced.R, reduced.z, p.N, with_covariance && l == 0, "the per-albedo cubic");
    out.theta[l] = p.theta(solve.phi);
    if (l == 0) out.unit_covariance = solve.unit_covariance;
  }
  return out;
}

// The reported and diagnostic per-albedo coefficients from the levels' θ (SIMEX, header).
void extrapolate(const LevelSolves& solves, bool eiv_correction, AlbedoFit& f) {
  for (int q = 0; q < 3; ++q) {
    const double t1 = solves.theta[0][q];
    const double t2 = 0.5 * (solves.theta[1][q] + solves.theta[2][q]);
    const double t3 = 0.5 * (solves.theta[3][q] + solves.theta[4][q]);
    const double t4 = 0.5 * (solves.theta[5][q] + solves.theta[6][q]);
    f.uncorrected[q] = t1;
    f.half_mean[q] = t2;
    // Cubic in v through v = 1, 2, 3, 4, extrapolated to v = 0: θ0 = 4θ1 − 6θ2 + 4θ3 − θ4.
    f.eiv_bias[q] = t1 - (4.0 * t1 - 6.0 * t2 + 4.0 * t3 - t4);
    // One order lower, quadratic through v = 1, 2, 3: θ0 = 3θ1 − 3θ2 + θ3.
    f.eiv_bias_quadratic[q] = t1 - (3.0 * t1 - 3.0 * t2 + t3);
    f.eiv_bias_two_point[q] = t2 - t1;
    f.theta[q] = eiv_correction ? t1 - f.eiv_bias[q] : t1;
  }
}

// True when no point's A carries Monte Carlo noise: both halves give the full estimate (a
// screen-space estimator's A). Every level then shares the regressors and differs only by ±c·δG,
// in which least squares is linear, so θ̂(v) = θ̂(1) for every v and the bias is exactly zero.
bool aIsNoiseFree(const SweepData& data) {
  for (std::size_t i = 0; i < data.points(); ++i) {
    if (data.half[0].A[i] != data.full.A[i] || data.half[1].A[i] != data.full.A[i]) return false;
  }
  return true;
}

// The exact zero bias of noise-free A, in place of the levels' rounding-level differences.
void clearEivBias(AlbedoFit& f) {
  f.eiv_bias = {};
  f.eiv_bias_quadratic = {};
  f.eiv_bias_two_point = {};
  f.half_mean = f.uncorrected;
  f.theta = f.uncorrected;
}

// The lines q(ρ) = q1 ρ + q0 of stage 2 and the map L = (RᵀR)⁻¹Rᵀ (2 × M) they apply.
struct Lines {
  MultiBounceCoeffs coeffs{};
  Eigen::MatrixXd L;
};

Lines fitLines(const std::vector<double>& albedos, const std::vector<Cubic>& theta, bool with_map) {
  const std::size_t M = albedos.size();
  std::vector<double> design(2 * M);
  for (std::size_t j = 0; j < M; ++j) {
    design[2 * j] = albedos[j];
    design[2 * j + 1] = 1.0;
  }
  Lines out;
  for (int q = 0; q < 3; ++q) {
    std::vector<double> y(M);
    for (std::size_t j = 0; j < M; ++j) y[j] = theta[j][q];
    const LinearSolve line = solveLinear(design, y, 2, with_map && q == 0,
                                         std::string("the line ") + kCubicNames[q] + "(rho)");
    out.coeffs[2 * q] = line.phi[0];
    out.coeffs[2 * q + 1] = line.phi[1];
    if (with_map && q == 0) {
      const Eigen::Matrix2d C = Eigen::Map<const Eigen::Matrix<double, 2, 2, Eigen::RowMajor>>(
          line.unit_covariance.data());
      out.L.resize(2, static_cast<Eigen::Index>(M));
      for (std::size_t j = 0; j < M; ++j) {
        out.L.col(static_cast<Eigen::Index>(j)) = C * Eigen::Vector2d(albedos[j], 1.0);
      }
    }
  }
  return out;
}

MultiBounceCoeffs applyLines(const Eigen::MatrixXd& L, const std::vector<Cubic>& theta) {
  MultiBounceCoeffs out{};
  for (int q = 0; q < 3; ++q) {
    for (int e = 0; e < 2; ++e) {
      for (std::size_t j = 0; j < theta.size(); ++j) {
        out[2 * q + e] += L(e, static_cast<Eigen::Index>(j)) * theta[j][q];
      }
    }
  }
  return out;
}

// Monte Carlo covariance of the stacked θ̂ (3M × 3M) by the weighted sandwich (header).
Eigen::MatrixXd monteCarloCovariance(const SweepData& data, const std::vector<double>& w,
                                     const std::vector<LevelSolves>& solves,
                                     const CubicParameterization& p) {
  const std::size_t M = data.albedos.size();
  const std::size_t n = data.points();
  const int N = p.N;
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> T(
      p.T.data(), 3, N);
  // Σ ψψᵀ as blocked rank updates of kSandwichBatch points at a time (fixed batches, so the sum's
  // order does not depend on anything but n).
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(N * M, N * M);
  Eigen::MatrixXd psi(N * M, kSandwichBatch);
  for (std::size_t begin = 0; begin < n; begin += kSandwichBatch) {
    const std::size_t count = std::min<std::size_t>(kSandwichBatch, n - begin);
    for (std::size_t b = 0; b < count; ++b) {
      const std::size_t i = begin + b;
      const double a = data.full.A[i];
      const double dA = 0.5 * (data.half[0].A[i] - data.half[1].A[i]);
      const double x[3] = {a * a * a, -a * a, a};
      const double dx[3] = {3.0 * a * a, -2.0 * a, 1.0};
      for (std::size_t j = 0; j < M; ++j) {
        const Cubic& t = solves[j].theta[0];
        const double r = data.full.G[j][i] - evalCubic(t, a);
        const double slope = (3.0 * t[0] * a - 2.0 * t[1]) * a + t[2];
        const double dG = 0.5 * (data.half[0].G[j][i] - data.half[1].G[j][i]);
        const double along_x = w[i] * (dG - slope * dA);
        const double along_dx = w[i] * r * dA;
        for (int u = 0; u < N; ++u) {
          double value = 0.0;
          for (int q = 0; q < 3; ++q) value += p.T[q * N + u] * (x[q] * along_x + dx[q] * along_dx);
          psi(N * j + u, static_cast<Eigen::Index>(b)) = value;
        }
      }
    }
    meat.selfadjointView<Eigen::Lower>().rankUpdate(psi.leftCols(count));
  }
  meat = meat.selfadjointView<Eigen::Lower>();
  Eigen::MatrixXd bread = Eigen::MatrixXd::Zero(3 * M, N * M);
  for (std::size_t j = 0; j < M; ++j) {
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
        C(solves[j].unit_covariance.data(), N, N);
    bread.block(3 * j, N * j, 3, N) = T * C;
  }
  return bread * meat * bread.transpose();
}

// Stage-1 Monte Carlo SE, iid SE and unweighted errors of every albedo.
void albedoErrors(const SweepData& data, const std::vector<double>& w,
                  const std::vector<LevelSolves>& solves, const CubicParameterization& p,
                  const Eigen::MatrixXd& cov, std::vector<AlbedoFit>& per_albedo) {
  const std::size_t n = data.points();
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> T(
      p.T.data(), 3, p.N);
  for (std::size_t j = 0; j < per_albedo.size(); ++j) {
    AlbedoFit& f = per_albedo[j];
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
        C(solves[j].unit_covariance.data(), p.N, p.N);
    const Eigen::Matrix3d unit = T * C * T.transpose();
    double weighted_rss = 0.0, sum2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double r0 = data.full.G[j][i] - evalCubic(f.uncorrected, data.full.A[i]);
      weighted_rss += w[i] * r0 * r0;
      const double r = data.full.G[j][i] - evalCubic(f.theta, data.full.A[i]);
      sum2 += r * r;
      f.max_abs = std::max(f.max_abs, std::abs(r));
    }
    const double sigma2 = weighted_rss / static_cast<double>(n - static_cast<std::size_t>(p.N));
    for (int q = 0; q < 3; ++q) {
      f.se[q] = std::sqrt(cov(3 * j + q, 3 * j + q));
      f.se_iid[q] = std::sqrt(unit(q, q) * sigma2);
    }
    f.rmse = std::sqrt(sum2 / static_cast<double>(n));
  }
}

}  // namespace

double remainingBias(double bias, double bias_quadratic, bool corrected) {
  return corrected ? std::abs(bias - bias_quadratic) : std::abs(bias);
}

MultiBounceCoeffs coefficientsFromStatistics(const LevelStatistics& sums,
                                             const std::vector<double>& albedos,
                                             const FitSettings& settings) {
  const CubicParameterization p = parameterization(settings);
  std::vector<Cubic> theta(albedos.size());
  for (std::size_t j = 0; j < albedos.size(); ++j) {
    AlbedoFit f;
    extrapolate(solveLevels(sums, j, p, false), settings.eiv_correction, f);
    theta[j] = f.theta;
  }
  if (settings.shape_constrained) {
    return solveShapeConstrained(profileObjective(sums[0], albedos));
  }
  return fitLines(albedos, theta, false).coeffs;
}

MultiBounceFit fitMultiBounce(const SweepData& data, const FitSettings& settings) {
  const std::size_t M = data.albedos.size();
  const CubicParameterization p = parameterization(settings);
  MultiBounceFit fit;
  fit.settings = settings;
  fit.weights = pointWeights(data, settings.weighting);
  fit.scene_stats = sceneStatistics(data, fit.weights);
  const LevelStatistics sums =
      sumScenes(fit.scene_stats, std::vector<bool>(data.scenes.size(), true));

  fit.a_noise_free = aIsNoiseFree(data);
  std::vector<LevelSolves> solves(M);
  fit.per_albedo.resize(M);
  for (std::size_t j = 0; j < M; ++j) {
    solves[j] = solveLevels(sums, j, p, true);
    fit.per_albedo[j].rho = data.albedos[j];
    fit.per_albedo[j].points = data.points();
    extrapolate(solves[j], settings.eiv_correction, fit.per_albedo[j]);
    if (fit.a_noise_free) clearEivBias(fit.per_albedo[j]);
  }
  const Eigen::MatrixXd cov = monteCarloCovariance(data, fit.weights, solves, p);
  albedoErrors(data, fit.weights, solves, p, cov, fit.per_albedo);

  // Stage 2: the lines, and the same linear map L applied to the diagnostics.
  const auto column = [&](Cubic AlbedoFit::*member) {
    std::vector<Cubic> out;
    for (const AlbedoFit& f : fit.per_albedo) out.push_back(f.*member);
    return out;
  };
  const std::vector<Cubic> reported = column(&AlbedoFit::theta);
  const Lines lines = fitLines(data.albedos, reported, true);
  LinearFit& lin = fit.linear;
  lin.coeffs = settings.shape_constrained
                   ? solveShapeConstrained(profileObjective(sums[0], data.albedos), kShapeGridNodes,
                                           &lin.solver_converged)
                   : lines.coeffs;
  lin.uncorrected = settings.shape_constrained
                        ? lin.coeffs
                        : fitLines(data.albedos, column(&AlbedoFit::uncorrected), false).coeffs;
  lin.eiv_bias = applyLines(lines.L, column(&AlbedoFit::eiv_bias));
  lin.eiv_bias_quadratic = applyLines(lines.L, column(&AlbedoFit::eiv_bias_quadratic));
  lin.eiv_bias_two_point = applyLines(lines.L, column(&AlbedoFit::eiv_bias_two_point));
  // Monte Carlo covariance of the six: Λ Cov(θ) Λᵀ, Λ(2q + e, 3j + q) = L(e, j).
  Eigen::MatrixXd Lambda = Eigen::MatrixXd::Zero(6, 3 * M);
  for (int q = 0; q < 3; ++q) {
    for (int e = 0; e < 2; ++e) {
      for (std::size_t j = 0; j < M; ++j) {
        Lambda(2 * q + e, 3 * j + q) = lines.L(e, static_cast<Eigen::Index>(j));
      }
    }
  }
  const Eigen::MatrixXd cov6 = Lambda * cov * Lambda.transpose();
  for (int r = 0; r < 6; ++r) {
    lin.se[r] = std::sqrt(cov6(r, r));
    for (int c = 0; c < 6; ++c) lin.mc_covariance[6 * r + c] = cov6(r, c);
  }
  for (int q = 0; q < 3; ++q) {
    double sum2 = 0.0;
    for (std::size_t j = 0; j < M; ++j) {
      const double r =
          reported[j][q] - (lin.coeffs[2 * q] * data.albedos[j] + lin.coeffs[2 * q + 1]);
      sum2 += r * r;
      lin.lack_of_fit_max[q] = std::max(lin.lack_of_fit_max[q], std::abs(r));
    }
    lin.lack_of_fit_rms[q] = std::sqrt(sum2 / static_cast<double>(M));
  }
  return fit;
}

CubicSolve fitCubic(const std::vector<double>& A, const std::vector<double>& G) {
  NormalEquations sums;
  const std::vector<double> unit(A.size(), 1.0);
  accumulate(sums, unit.data(), A.data(), {G.data()}, A.size());
  const CubicParameterization p = freeCubic();
  const ReducedProblem reduced = reduceProblem(sums, 0, p);
  const LinearSolve solve = solveLinear(reduced.R, reduced.z, 3, true, "the cubic");
  CubicSolve out;
  out.theta = p.theta(solve.phi);
  std::copy(solve.unit_covariance.begin(), solve.unit_covariance.end(),
            out.unit_covariance.begin());
  for (std::size_t i = 0; i < A.size(); ++i) {
    const double r = G[i] - evalCubic(out.theta, A[i]);
    out.rss += r * r;
  }
  return out;
}

}  // namespace gtbake
