#include "gtso/s3_closed_form.h"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>
#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/error.h"
#include "common/rng.h"
#include "gtso/gtso_integrator.h"

namespace gtbake::gtso {

namespace {

constexpr int kN = kGtsoS3ClosedFormCoeffs;
using Jet = ceres::Jet<double, kN>;

constexpr double kStepLobeWidths = 6.0;  // near-step cones: within 6 alpha + 0.02 rad of the step
constexpr double kStepFloor = 0.02;
constexpr double kGrazingCos = 0.1;                 // grazing lobes: cos theta_o in [0, 0.1]
constexpr double kNormalCos = 0.9;                  // near-normal lobes: cos theta_o in [0.9, 1]
constexpr double kRoughBand = 0.1;                  // the r_p >= 0.1 target band
constexpr std::uint64_t kPointStream = 0x53334346;  // "S3CF": apart from makeErrorPoints' streams
// Point sets of the stage: lobes x cones; training at half the bake's cells (integration error
// ~4x the bake's 1.6e-4, far below the fit's residuals), validation at the bake's cells.
constexpr int kValidationLobesDivisor = 4;  // validation lobes = training lobes / 4
constexpr int kConesPerLobe = 32;
constexpr int kTrainCellsDivisor = 2;
constexpr double kMinReciprocalCondition = 1e-14;  // J^T J: smallest / largest eigenvalue
constexpr double kTargetMax = 0.02;                // docs/gtso.md §7, r_p >= 0.1
constexpr double kTargetRms = 0.005;

// One lobe's residuals: S_form(A_j; k) - S_j for its points. The lobe parameters (median, slopes)
// and their gradients in k come from one Jet evaluation; each point adds the chain rule.
class LobeCost final : public ceres::CostFunction {
 public:
  LobeCost(const GtsoPoint* p, const double* exact, int count) : p_(p), exact_(exact), n_(count) {
    set_num_residuals(count);
    mutable_parameter_block_sizes()->push_back(kN);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* k = parameters[0];
    const double mu = std::cos(p_[0].theta_o), rp = p_[0].r_p;
    std::array<Jet, kN> kj;
    for (int i = 0; i < kN; ++i) kj[i] = Jet(k[i], i);
    const GtsoS3ClosedFormLobe<Jet> lobe = gtsoS3ClosedFormLobe(kj.data(), mu, rp);
    for (int j = 0; j < n_; ++j) {
      const double A = p_[j].A;
      double* row =
          jacobians != nullptr && jacobians[0] != nullptr ? jacobians[0] + j * kN : nullptr;
      if (!(A > 0.0) || !(A < 1.0)) {
        residuals[j] = (A > 0.0 ? 1.0 : 0.0) - exact_[j];
        if (row != nullptr) std::fill(row, row + kN, 0.0);
        continue;
      }
      const double u = 0.5 * std::log(A / (1.0 - A));
      const double d = u - lobe.median.a;
      const Jet& slope = d < 0.0 ? lobe.slopeLo : lobe.slopeHi;
      const double w = lobe.tailWeight.a;
      const double core = gtsoLogistic(d * slope.a);
      const double tail = gtsoLogistic(d * lobe.tailSlope.a);
      residuals[j] = (1.0 - w) * core + w * tail - exact_[j];
      if (row != nullptr) {
        const double dc = (1.0 - w) * core * (1.0 - core), dt = w * tail * (1.0 - tail);
        for (int i = 0; i < kN; ++i) {
          row[i] = dc * (d * slope.v[i] - slope.a * lobe.median.v[i]) +
                   dt * (d * lobe.tailSlope.v[i] - lobe.tailSlope.a * lobe.median.v[i]) +
                   (tail - core) * lobe.tailWeight.v[i];
        }
      }
    }
    return true;
  }

 private:
  const GtsoPoint* p_;
  const double* exact_;
  int n_;
};

// The warm start of `gtbake gtso`: the coefficients of a cold fit (bench_s3_closed_form from
// closedFormStart(), same training set), so the fit in the pipeline converges in a few
// iterations; the fit itself decides the shipped values.
// clang-format off
constexpr S3ClosedFormCoeffs kWarmStart = {
    9.75488264, -3.3189302, -5.4086258, 5.54219672, -5.10556755, -0.989231607, -10.4967237, 10.9599926, -0.252841486, -0.631443479,  // P_a
    2.19622176, -0.019471876, 3.25174535, -1.06119822, 1.02771828, -3.3431972, -1.13682657, -0.310314097, -1.09337936, -0.119492186,  // P_b
    3.44109176, -1.56064162, -2.2377054, 0.927638977, -1.09976239, 0.37817493, -3.4783804, 3.42301438, 0.557966003, -0.701816053,  // P_c
    0.283472897, 0.680386573, 0.744310329, -0.0592264792, -0.40008201, -0.506193609, -1.10519423, -0.0984669146, 0.117260104, 2.86761599,  // P_0lo
    -2.85528145, -4.31650337, 67.8226938, 0.867357916, 0.0178802791, -43.8099173, 4.59089268, 4.28756787, -61.6178144, -1.95824495,  // P_wlo
    0.615088449, 0.622007007, -0.395059731, 0.37898799, -0.509276148, 0.00545769881, -0.369843704, -0.43780872, -0.0257470419, 2.19508487,  // P_0hi
    37.9552625, -2.7299605, 2.13119594, -1.9104191, -0.299448573, -17.2145903, -74.5344546, 3.3376914, 2.82412879, 36.1882954,  // P_whi
    -4.84618248, -8.2231093, 10.6116546, 1.69502707, 1.75196444, -8.23827992, 10.9055298, 5.96062919, 2.71711376, -9.62756796,  // P_w
    0.288591776, 0.277522305, 2.96195151, 3.92612564, -3.25230289, -3.22887143, -1.23453324, 4.61708739, -5.63397068, 0.609188676,  // P_t
};
// clang-format on

}  // namespace

ErrorPoints makeClosedFormPoints(int lobes, int perLobe, std::uint64_t seed, int cells) {
  const CounterRng rng(seed, kPointStream);
  ErrorPoints out = sizedErrorPoints(lobes, perLobe);
  tbb::parallel_for(0, lobes, [&](int l) {
    const auto u = rng.uniform4(static_cast<std::uint64_t>(l), 0);
    const double rp = u[0];
    double cosO = u[1];
    if (l % 4 == 1) cosO = kGrazingCos * u[1];
    if (l % 4 == 2) cosO = kNormalCos + (1.0 - kNormalCos) * u[1];
    const double theta_o = std::acos(cosO);
    std::vector<double> cones(perLobe);
    for (int k = 0; k < perLobe; ++k) {
      const auto v = rng.uniform4(static_cast<std::uint64_t>(l), 1 + k);
      double A = v[0];
      if (k % 2 == 1) {
        A = stepWindowA(theta_o, kStepLobeWidths * rp * rp + kStepFloor, v[1]);
      }
      out.points[static_cast<std::size_t>(l) * perLobe + k] = {A, theta_o, rp, theta_o};
      cones[k] = std::sqrt(std::clamp(1.0 - A, 0.0, 1.0));
    }
    const std::vector<double> s = specularOcclusion(rp, cosO, {Vec3{0.0, 0.0, 1.0}}, cones, cells);
    for (int k = 0; k < perLobe; ++k) out.exact[static_cast<std::size_t>(l) * perLobe + k] = s[k];
  });
  return out;
}

S3ClosedFormCoeffs closedFormWarmStart() {
  return kWarmStart;
}

S3ClosedFormCoeffs closedFormStart() {
  S3ClosedFormCoeffs k{};
  k.fill(0.0);
  k[7 * kGtsoS3ClosedFormBasis] = -2.0;           // tail weight 0.12
  k[8 * kGtsoS3ClosedFormBasis] = std::log(2.0);  // tail slope 2: S ~ A far below the step
  return k;
}

S3ClosedFormFit fitS3ClosedForm(const ErrorPoints& train, int perLobe,
                                const S3ClosedFormCoeffs& start) {
  if (perLobe < 1 || train.points.size() % static_cast<std::size_t>(perLobe) != 0) {
    throw Error("closed-form fit: points must come in whole lobes");
  }
  S3ClosedFormFit fit;
  fit.k = start;
  fit.points = static_cast<int>(train.points.size());
  ceres::Problem::Options problemOptions;
  ceres::Problem problem(problemOptions);
  for (std::size_t i = 0; i < train.points.size(); i += perLobe) {
    problem.AddResidualBlock(new LobeCost(&train.points[i], &train.exact[i], perLobe), nullptr,
                             fit.k.data());
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;  // 70 unknowns, ~30k residuals
  options.num_threads = 1;                                    // deterministic
  options.max_num_iterations = 200;
  options.function_tolerance = 1e-8;  // relative objective change: far below the residuals
  options.parameter_tolerance = 1e-10;
  options.gradient_tolerance = 1e-12;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable()) {
    throw Error("closed-form S3 fit failed: " + summary.message);
  }
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.objective = summary.final_cost;
  fit.initial_objective = summary.initial_cost;
  fit.rms = std::sqrt(2.0 * fit.objective / std::max(fit.points, 1));

  // Standard errors from J^T J at the optimum (90 x 90, accumulated in double from one Jacobian
  // evaluation), inverted by its eigendecomposition; empty if it is rank deficient.
  ceres::CRSMatrix jacobian;
  double cost = 0.0;
  problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, &jacobian);
  Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(kN, kN);
  for (int r = 0; r < jacobian.num_rows; ++r) {
    Eigen::VectorXd row = Eigen::VectorXd::Zero(kN);
    for (int e = jacobian.rows[r]; e < jacobian.rows[r + 1]; ++e) {
      row[jacobian.cols[e]] = jacobian.values[e];
    }
    jtj.selfadjointView<Eigen::Lower>().rankUpdate(row);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(
      jtj.selfadjointView<Eigen::Lower>().toDenseMatrix());
  const Eigen::VectorXd& lambda = eigen.eigenvalues();
  if (lambda.minCoeff() > kMinReciprocalCondition * lambda.maxCoeff()) {
    const Eigen::MatrixXd cov = eigen.eigenvectors() * lambda.cwiseInverse().asDiagonal() *
                                eigen.eigenvectors().transpose();
    const double variance = 2.0 * fit.objective / std::max(fit.points - kN, 1);
    for (int i = 0; i < kN; ++i) {
      fit.standard_errors.push_back(std::sqrt(std::max(0.0, cov(i, i)) * variance));
    }
  }
  // The objective at the coefficients rounded to float, as the header and shaders ship them.
  S3ClosedFormCoeffs rounded;
  for (int i = 0; i < kN; ++i) rounded[i] = static_cast<float>(fit.k[i]);
  double sum = 0.0;
  for (std::size_t i = 0; i < train.points.size(); ++i) {
    const double d = closedFormAt(rounded, train.points[i]) - train.exact[i];
    sum += d * d;
  }
  fit.objective_float_k = 0.5 * sum;
  return fit;
}

float closedFormAt(const S3ClosedFormCoeffs& k, const GtsoPoint& p) {
  float kf[kN];
  for (int i = 0; i < kN; ++i) kf[i] = static_cast<float>(k[i]);
  return gtsoS3ClosedForm(kf, static_cast<float>(p.A), static_cast<float>(std::cos(p.theta_o)),
                          static_cast<float>(p.r_p));
}

void addClosedFormErrors(const S3ClosedFormCoeffs& k, const ErrorPoints& pts, ClosedFormErrors& e) {
  for (std::size_t i = 0; i < pts.points.size(); ++i) {
    const GtsoPoint& p = pts.points[i];
    const double d = std::abs(static_cast<double>(closedFormAt(k, p)) - pts.exact[i]);
    ClosedFormBand& b = p.r_p >= kRoughBand ? e.rough : e.smooth;
    ++b.count;
    b.stats.rms += d * d;
    if (d > b.stats.max) {
      b.stats.max = d;
      b.stats.worst = p;
    }
  }
}

void finishClosedFormErrors(ClosedFormErrors& e) {
  for (ClosedFormBand* b : {&e.rough, &e.smooth}) {
    b->stats.rms = b->count > 0 ? std::sqrt(b->stats.rms / b->count) : 0.0;
  }
}

ClosedFormErrors closedFormErrors(const S3ClosedFormCoeffs& k, const ErrorPoints& pts) {
  ClosedFormErrors e;
  addClosedFormErrors(k, pts, e);
  finishClosedFormErrors(e);
  return e;
}

namespace {

nlohmann::json bandJson(const ClosedFormBand& b) {
  const GtsoPoint& w = b.stats.worst;
  return {
      {"max", b.stats.max},
      {"rms", b.stats.rms},
      {"points", b.count},
      {"worst_point",
       {{"A", w.A}, {"cos_theta_o", std::cos(w.theta_o)}, {"theta_o", w.theta_o}, {"r_p", w.r_p}}}};
}

nlohmann::json errorsJson(const ClosedFormErrors& e) {
  return {{"r_p_ge_0.1", bandJson(e.rough)}, {"r_p_lt_0.1", bandJson(e.smooth)}};
}

}  // namespace

ClosedFormStage runClosedFormStage(const std::vector<const ErrorPoints*>& tests,
                                   const std::vector<std::uint64_t>& test_seeds, int cells,
                                   int train_lobes) {
  const auto t0 = std::chrono::steady_clock::now();
  const int trainCells = std::max(4, cells / kTrainCellsDivisor);
  const ErrorPoints train =
      makeClosedFormPoints(train_lobes, kConesPerLobe, kClosedFormTrainSeed, trainCells);
  const ErrorPoints validation =
      makeClosedFormPoints(std::max(1, train_lobes / kValidationLobesDivisor), kConesPerLobe,
                           kClosedFormValidationSeed, cells);
  const S3ClosedFormFit fit = fitS3ClosedForm(train, kConesPerLobe, closedFormWarmStart());
  const ClosedFormErrors val = closedFormErrors(fit.k, validation);
  ClosedFormErrors test;
  std::size_t testPoints = 0;
  for (const ErrorPoints* t : tests) {
    addClosedFormErrors(fit.k, *t, test);
    testPoints += t->points.size();
  }
  finishClosedFormErrors(test);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  ClosedFormStage out;
  out.k = fit.k;
  nlohmann::json& j = out.json;
  j["function"] = "gtsoS3ClosedForm(A, cosBeta, rp): cosBeta = cos theta_o (bent normal = n)";
  j["form"] =
      "S = (1-w) L(z) + w L(p_t d), L(x) = 1/(1+exp(-x)), d = u - u_m, u = log(A/(1-A))/2, "
      "z = p_lo d (d<0) or p_hi d; exp(2 u_m) = (tan^2 theta_o + a)/(1 + b tan^2 theta_o) "
      "exp(2 alpha P_c), a = alpha^2 exp(P_a), b = alpha^2 exp(P_b); p_lo = hypot(exp(P_0lo), "
      "h exp(-P_wlo)), p_hi = hypot(exp(P_0hi), h exp(-P_whi)), h = sin(2 theta_o)/(2 alpha); "
      "w = L(P_w), p_t = exp(P_t); alpha = r_p^2 + 1e-4; each P = sum_i k[s*10+i] basis_i";
  j["basis"] =
      "1, m, r_p, m r_p, m^2, r_p^2, q, q m, q r_p, q^2; m = sqrt(cos theta_o), q = h/(1+h)";
  j["coefficient_sets"] = {"P_a", "P_b", "P_c", "P_0lo", "P_wlo", "P_0hi", "P_whi", "P_w", "P_t"};
  j["coefficients"] = fit.k;
  j["exact_limits"] = "S = 0 at A = 0 and S = 1 at A = 1 exactly; monotone in A";
  j["alu"] = kGtsoS3ClosedFormAlu;
  j["objective"] = {
      {"definition",
       "least squares: (1/2) sum over the training points of (S_form - S3_exact)^2, Ceres "
       "Levenberg-Marquardt, dense normal Cholesky, single-threaded, from the warm start"},
      {"value", fit.objective},
      {"initial", fit.initial_objective},
      {"rms_residual", fit.rms},
      {"at_float_coefficients", fit.objective_float_k},
      {"iterations", fit.iterations},
      {"converged", fit.converged}};
  j["flatness"] = {
      {"standard_errors", fit.standard_errors},
      {"definition",
       "sqrt(diag((J^T J)^-1) * 2 objective / (points - coefficients)) at the optimum (J^T "
       "J from the Jacobian, eigendecomposition); a coefficient moved by one standard error raises "
       "the objective "
       "by about 1/2 residual variance (0.5 * rms_residual^2); empty if rank deficient"}};
  j["training"] = {{"points", train.points.size()},
                   {"lobes", train_lobes},
                   {"points_per_lobe", kConesPerLobe},
                   {"seed", kClosedFormTrainSeed},
                   {"integrator_cells", trainCells},
                   {"distribution",
                    "lobes by l mod 4: uniform cos theta_o, grazing (cos theta_o < 0.1), near "
                    "normal (cos theta_o > 0.9), uniform; r_p uniform; per lobe half the points A "
                    "uniform, half alpha_v within 6 alpha + 0.02 rad of the step alpha_v = "
                    "theta_o"}};
  j["validation"] = {{"points", validation.points.size()},
                     {"seed", kClosedFormValidationSeed},
                     {"integrator_cells", cells},
                     {"distribution", "as training, another seed"},
                     {"errors", errorsJson(val)}};
  j["test"] = {{"points", testPoints},
               {"sets", "gtso's end-to-end 3D point sets (end_to_end.points): uniform and stress"},
               {"seeds", test_seeds},
               {"integrator_cells", cells},
               {"errors", errorsJson(test)}};
  j["targets"] = {{"band", "r_p >= 0.1"}, {"max", kTargetMax}, {"rms", kTargetRms}};
  j["meets_targets"] = test.rough.stats.max <= kTargetMax && test.rough.stats.rms <= kTargetRms;
  j["fit_s"] = seconds;
  return out;
}

}  // namespace gtbake::gtso
