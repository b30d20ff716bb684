#include "gtso/cone_fit.h"

#include <ceres/ceres.h>

#include <cmath>

#include "common/error.h"
#include "gtso/cone_intersection.h"

namespace gtbake::gtso {

namespace {

// u = 0.12 to start: between Uludag's 0.244 and the paper's 0.01.
constexpr double kInitialZ = -2.0;
// z is bounded to |z| <= 40 (u in [4e-18, 1 - 4e-18]): where S_cone prefers ever wider specular
// cones (small samples; the objective is flat toward u -> 0, docs/gtso.md §4) the fit stops at
// the bound instead of running to z ~ -400, where the residuals no longer depend on z.
constexpr double kZBound = 40.0;

double uFromZ(double z) {
  return 1.0 / (1.0 + std::exp(-z));
}

// One sample's residual S_cone(u(z)) - S3; numeric (central) derivative in z.
struct ConeResidual {
  GtsoPoint p;
  double target;
  RoughnessConvention convention;
  bool operator()(const double* z, double* residual) const {
    residual[0] = coneModel(p, uFromZ(z[0]), convention) - target;
    return true;
  }
};

template <typename F>
void forEachFitSample(const S3Samples& s3, double rp_min, F&& f) {
  for (std::size_t i = 0; i < s3.points.size(); ++i) {
    const GtsoPoint& p = s3.points[i];
    if (p.r_p > 0.0 && p.r_p >= rp_min - 1e-12) f(p, s3.values[i]);
  }
}

}  // namespace

double coneModel(const GtsoPoint& p, double u, RoughnessConvention convention) {
  const double w = convention == RoughnessConvention::kAlpha ? p.r_p * p.r_p : p.r_p;
  const double alphaV = std::acos(std::sqrt(std::clamp(1.0 - p.A, 0.0, 1.0)));
  return coneSpecularOcclusion(alphaV, specularConeAperture(u, w), p.theta_o);
}

ConeErrors coneErrors(const S3Samples& s3, double u, RoughnessConvention convention,
                      double rp_min) {
  ConeErrors e;
  double sum = 0.0;
  forEachFitSample(s3, rp_min, [&](const GtsoPoint& p, double s) {
    const double d = coneModel(p, u, convention) - s;
    sum += d * d;
    e.max_abs = std::max(e.max_abs, std::abs(d));
    ++e.count;
  });
  e.rmse = std::sqrt(sum / std::max(e.count, 1));
  return e;
}

ConeFit fitConeU(const S3Samples& s3, RoughnessConvention convention, double rp_min) {
  double z = kInitialZ;
  ceres::Problem problem;
  forEachFitSample(s3, rp_min, [&](const GtsoPoint& p, double s) {
    problem.AddResidualBlock(new ceres::NumericDiffCostFunction<ConeResidual, ceres::CENTRAL, 1, 1>(
                                 new ConeResidual{p, s, convention}),
                             nullptr, &z);
  });
  if (problem.NumResidualBlocks() > 0) {
    problem.SetParameterLowerBound(&z, 0, -kZBound);
    problem.SetParameterUpperBound(&z, 0, kZBound);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.num_threads = 1;  // deterministic
  options.function_tolerance = 1e-14;
  options.parameter_tolerance = 1e-12;
  options.max_num_iterations = 200;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable() || summary.termination_type == ceres::NO_CONVERGENCE) {
    throw Error("cone-aperture fit did not converge: " + summary.message);
  }
  ceres::Covariance::Options covOptions;
  ceres::Covariance covariance(covOptions);
  std::vector<std::pair<const double*, const double*>> blocks = {{&z, &z}};
  double varZ = 0.0;
  if (!covariance.Compute(blocks, &problem) || !covariance.GetCovarianceBlock(&z, &z, &varZ)) {
    throw Error("cone-aperture fit: covariance is rank deficient");
  }
  ConeFit fit;
  fit.u = uFromZ(z);
  fit.errors = coneErrors(s3, fit.u, convention, rp_min);
  const double residualVariance =
      fit.errors.rmse * fit.errors.rmse * fit.errors.count / std::max(fit.errors.count - 1, 1);
  fit.u_se = fit.u * (1.0 - fit.u) * std::sqrt(varZ * residualVariance);
  return fit;
}

}  // namespace gtbake::gtso
