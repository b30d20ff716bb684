#include "fit/multibounce_fit.h"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"

namespace gtbake {

namespace {

// Points per residual block (points; one block per 256 points keeps Ceres' per-block overhead
// small next to the arithmetic, and autodiff stays cheap with 3 parameters).
constexpr int kChunk = 256;
// Noise levels of the errors-in-variables extrapolation (see fitMultiBounce).
constexpr int kLevels = 5;

// Residuals of the cubic over up to kChunk points: r_i = G_i − (a A_i³ − b A_i² + c A_i).
// Unused slots of the last chunk are zero with zero derivative, so they add nothing to JᵀJ.
struct CubicChunkResidual {
  const double* A;
  const double* G;
  int count;

  template <typename T>
  bool operator()(const T* theta, T* residual) const {
    for (int i = 0; i < kChunk; ++i) {
      if (i < count) {
        const T a(A[i]);
        residual[i] = T(G[i]) - ((theta[0] * a - theta[1]) * a + theta[2]) * a;
      } else {
        residual[i] = T(0.0);
      }
    }
    return true;
  }

  static ceres::CostFunction* Create(const double* A, const double* G, int count) {
    return new ceres::AutoDiffCostFunction<CubicChunkResidual, kChunk, 3>(
        new CubicChunkResidual{A, G, count});
  }
};

// Residual of one coefficient's line in ρ: r_j = q_j − (q1 ρ_j + q0).
struct LineResidual {
  double rho;
  double q;

  template <typename T>
  bool operator()(const T* line, T* residual) const {
    residual[0] = T(q) - (line[0] * T(rho) + line[1]);
    return true;
  }

  static ceres::CostFunction* Create(double rho, double q) {
    return new ceres::AutoDiffCostFunction<LineResidual, 1, 2>(new LineResidual{rho, q});
  }
};

ceres::Solver::Options solverOptions() {
  ceres::Solver::Options options;
  // QR of the Jacobian: the cubic's XᵀX has condition ~1e5, and at the optimum the normal
  // equations' predicted decrease drowns in rounding (Ceres then rejects the steps as invalid).
  options.linear_solver_type = ceres::DENSE_QR;
  // The problem is linear: let the first Levenberg–Marquardt step be the Gauss–Newton step.
  options.initial_trust_region_radius = 1e16;
  options.num_threads = 1;  // one thread per solve: Ceres' multi-threaded reductions reorder sums
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  options.logging_type = ceres::SILENT;
  return options;
}

void requireConverged(const ceres::Solver::Summary& summary, const std::string& what) {
  if (summary.termination_type != ceres::CONVERGENCE || !summary.IsSolutionUsable()) {
    throw Error("Ceres did not converge on " + what + ": " + summary.message);
  }
}

// (JᵀJ)⁻¹ of the parameter block, from ceres::Covariance.
template <int N>
std::array<double, N * N> unitCovariance(ceres::Problem& problem, double* block,
                                         const std::string& what) {
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::DENSE_SVD;
  options.num_threads = 1;
  ceres::Covariance covariance(options);
  std::vector<std::pair<const double*, const double*>> blocks = {{block, block}};
  std::array<double, N * N> out{};
  if (!covariance.Compute(blocks, &problem) ||
      !covariance.GetCovarianceBlock(block, block, out.data())) {
    throw Error("Ceres covariance failed on " + what + " (rank-deficient data?)");
  }
  return out;
}

// Fits q(ρ) = q1 ρ + q0 through Ceres; returns the line and (RᵀR)⁻¹.
std::pair<std::array<double, 2>, std::array<double, 4>> fitLine(const std::vector<double>& rho,
                                                                const std::vector<double>& q,
                                                                const std::string& what) {
  std::array<double, 2> line = {0.0, 0.0};
  ceres::Problem problem;
  for (std::size_t j = 0; j < rho.size(); ++j) {
    problem.AddResidualBlock(LineResidual::Create(rho[j], q[j]), nullptr, line.data());
  }
  ceres::Solver::Summary summary;
  ceres::Solve(solverOptions(), &problem, &summary);
  requireConverged(summary, what);
  return {line, unitCovariance<2>(problem, line.data(), what)};
}

Eigen::Matrix3d toMatrix(const std::array<double, 9>& m) {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(m.data());
}

}  // namespace

double evalCubic(const Cubic& theta, double A) {
  return ((theta[0] * A - theta[1]) * A + theta[2]) * A;
}

Cubic cubicAt(const MultiBounceCoeffs& k, double rho) {
  return {k[0] * rho + k[1], k[2] * rho + k[3], k[4] * rho + k[5]};
}

double evalMultiBounce(const MultiBounceCoeffs& coeffs, double A, double rho) {
  return evalCubic(cubicAt(coeffs, rho), A);
}

CubicSolve fitCubic(const std::vector<double>& A, const std::vector<double>& G,
                    bool with_covariance) {
  CubicSolve out;
  out.points = A.size();
  ceres::Problem::Options problem_options;
  ceres::Problem problem(problem_options);
  for (std::size_t begin = 0; begin < A.size(); begin += kChunk) {
    const int count = static_cast<int>(std::min<std::size_t>(kChunk, A.size() - begin));
    problem.AddResidualBlock(CubicChunkResidual::Create(&A[begin], &G[begin], count), nullptr,
                             out.theta.data());
  }
  ceres::Solver::Summary summary;
  ceres::Solve(solverOptions(), &problem, &summary);
  requireConverged(summary, "the per-albedo cubic");
  if (with_covariance) {
    out.unit_covariance = unitCovariance<3>(problem, out.theta.data(), "the per-albedo cubic");
  }
  for (std::size_t i = 0; i < A.size(); ++i) {
    const double r = G[i] - evalCubic(out.theta, A[i]);
    out.rss += r * r;
  }
  return out;
}

MultiBounceFit fitMultiBounce(const SweepData& data, bool eiv_correction) {
  const std::size_t M = data.albedos.size();
  const std::size_t n = data.points();
  // Noise levels (SIMEX with the sweep's own noise, docs/fit.md §4): d_i = (h0_i − h1_i)/2 has
  // the variance of the full estimate and is uncorrelated with it, so full + c·d has (1 + c²)
  // times the full estimate's noise variance, with the same A–G correlation. c = ±1 are the two
  // halves. Solves: [level][albedo] for c = 0, +1, −1, +√2, −√2.
  const double kLevelC[kLevels] = {0.0, 1.0, -1.0, std::sqrt(2.0), -std::sqrt(2.0)};
  std::vector<PointSet> sets(kLevels);
  for (int l = 0; l < kLevels; ++l) {
    const double c = 0.5 * kLevelC[l];
    sets[l].A.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      sets[l].A[i] = data.full.A[i] + c * (data.half[0].A[i] - data.half[1].A[i]);
    }
    sets[l].G.assign(M, std::vector<double>(n));
    for (std::size_t j = 0; j < M; ++j) {
      for (std::size_t i = 0; i < n; ++i) {
        sets[l].G[j][i] = data.full.G[j][i] + c * (data.half[0].G[j][i] - data.half[1].G[j][i]);
      }
    }
  }
  // Independent solves run in parallel; each writes its own slot, so the result does not
  // depend on the thread count.
  std::vector<CubicSolve> solves(kLevels * M);
  tbb::parallel_for(std::size_t{0}, kLevels * M, [&](std::size_t s) {
    solves[s] = fitCubic(sets[s / M].A, sets[s / M].G[s % M], s < M);
  });

  // Monte Carlo covariance of the stacked full-estimate θ̂ (3M), by the sandwich C (Σ ψψᵀ) C.
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(3 * M, 3 * M);
  Eigen::VectorXd psi(3 * M);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = data.full.A[i];
    const double dA = 0.5 * (data.half[0].A[i] - data.half[1].A[i]);
    const Eigen::Vector3d x(a * a * a, -a * a, a);
    const Eigen::Vector3d dx(3.0 * a * a, -2.0 * a, 1.0);
    for (std::size_t j = 0; j < M; ++j) {
      const Cubic& t = solves[j].theta;
      const double r = data.full.G[j][i] - evalCubic(t, a);
      const double slope = (3.0 * t[0] * a - 2.0 * t[1]) * a + t[2];
      const double dG = 0.5 * (data.half[0].G[j][i] - data.half[1].G[j][i]);
      psi.segment<3>(3 * j) = x * (dG - slope * dA) + dx * (r * dA);
    }
    meat.selfadjointView<Eigen::Lower>().rankUpdate(psi);
  }
  meat = meat.selfadjointView<Eigen::Lower>();
  Eigen::MatrixXd bread = Eigen::MatrixXd::Zero(3 * M, 3 * M);
  for (std::size_t j = 0; j < M; ++j) {
    bread.block<3, 3>(3 * j, 3 * j) = toMatrix(solves[j].unit_covariance);
  }
  const Eigen::MatrixXd cov = bread * meat * bread;

  MultiBounceFit fit;
  fit.eiv_corrected = eiv_correction;
  for (std::size_t j = 0; j < M; ++j) {
    AlbedoFit f;
    f.rho = data.albedos[j];
    f.points = n;
    const CubicSolve& full = solves[j];
    const Eigen::Matrix3d unit = toMatrix(full.unit_covariance);
    const double sigma2 = full.rss / static_cast<double>(n - 3);
    for (int q = 0; q < 3; ++q) {
      f.uncorrected[q] = full.theta[q];
      // θ at noise variance v × (the full estimate's): v = 1, 2 (halves), 3.
      const double t1 = full.theta[q];
      const double t2 = 0.5 * (solves[M + j].theta[q] + solves[2 * M + j].theta[q]);
      const double t3 = 0.5 * (solves[3 * M + j].theta[q] + solves[4 * M + j].theta[q]);
      f.half_mean[q] = t2;
      // Quadratic in v through v = 1, 2, 3, extrapolated to v = 0: θ0 = 3θ1 − 3θ2 + θ3.
      f.eiv_bias[q] = t1 - (3.0 * t1 - 3.0 * t2 + t3);
      f.eiv_bias_linear[q] = t2 - t1;
      f.theta[q] = eiv_correction ? f.uncorrected[q] - f.eiv_bias[q] : f.uncorrected[q];
      f.se[q] = std::sqrt(cov(3 * j + q, 3 * j + q));
      f.se_iid[q] = std::sqrt(unit(q, q) * sigma2);
    }
    double sum2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double r = data.full.G[j][i] - evalCubic(f.theta, data.full.A[i]);
      sum2 += r * r;
      f.max_abs = std::max(f.max_abs, std::abs(r));
    }
    f.rmse = std::sqrt(sum2 / static_cast<double>(n));
    fit.per_albedo.push_back(f);
  }

  // Stage 2. The line is L·q with L = (RᵀR)⁻¹Rᵀ (R rows (ρ_j, 1)); Ceres gives (RᵀR)⁻¹.
  const char* names[3] = {"a", "b", "c"};
  for (int q = 0; q < 3; ++q) {
    std::vector<double> reported(M), raw(M), bias(M), bias_linear(M);
    for (std::size_t j = 0; j < M; ++j) {
      reported[j] = fit.per_albedo[j].theta[q];
      raw[j] = fit.per_albedo[j].uncorrected[q];
      bias[j] = fit.per_albedo[j].eiv_bias[q];
      bias_linear[j] = fit.per_albedo[j].eiv_bias_linear[q];
    }
    const std::string what = std::string("the line ") + names[q] + "(rho)";
    const auto [line, unit] = fitLine(data.albedos, reported, what);
    const auto raw_line = fitLine(data.albedos, raw, what).first;
    Eigen::MatrixXd L(2, M);
    const Eigen::Matrix2d C =
        Eigen::Map<const Eigen::Matrix<double, 2, 2, Eigen::RowMajor>>(unit.data());
    for (std::size_t j = 0; j < M; ++j) L.col(j) = C * Eigen::Vector2d(data.albedos[j], 1.0);
    Eigen::MatrixXd cov_q(M, M);
    for (std::size_t j = 0; j < M; ++j) {
      for (std::size_t k = 0; k < M; ++k) cov_q(j, k) = cov(3 * j + q, 3 * k + q);
    }
    const Eigen::Matrix2d cov_line = L * cov_q * L.transpose();
    double misfit2 = 0.0;
    for (std::size_t j = 0; j < M; ++j) {
      const double r = reported[j] - (line[0] * data.albedos[j] + line[1]);
      misfit2 += r * r;
    }
    const double dof = static_cast<double>(M) - 2.0;
    for (int e = 0; e < 2; ++e) {
      const Eigen::Vector2d b = L * Eigen::Map<const Eigen::VectorXd>(bias.data(), M);
      const Eigen::Vector2d bl = L * Eigen::Map<const Eigen::VectorXd>(bias_linear.data(), M);
      fit.linear.eiv_bias_linear[2 * q + e] = bl[e];
      fit.linear.coeffs[2 * q + e] = line[e];
      fit.linear.uncorrected[2 * q + e] = raw_line[e];
      fit.linear.eiv_bias[2 * q + e] = b[e];
      fit.linear.se[2 * q + e] = std::sqrt(cov_line(e, e));
      fit.linear.misfit_se[2 * q + e] = dof > 0 ? std::sqrt(C(e, e) * misfit2 / dof) : 0.0;
    }
    fit.linear.misfit_rms[q] = std::sqrt(misfit2 / static_cast<double>(M));
  }
  return fit;
}

}  // namespace gtbake
