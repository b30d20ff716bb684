#include "fit/ceres_linear.h"

#include <ceres/ceres.h>

#include <utility>

#include "common/error.h"

namespace gtbake {

namespace {

// r = M φ − y with the exact Jacobian M (the problem is linear, autodiff would only copy M).
class LinearCost : public ceres::CostFunction {
 public:
  LinearCost(const std::vector<double>& M, const std::vector<double>& y, int N)
      : M_(M), y_(y), n_(N) {
    set_num_residuals(static_cast<int>(y.size()));
    mutable_parameter_block_sizes()->push_back(N);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* phi = parameters[0];
    for (std::size_t r = 0; r < y_.size(); ++r) {
      double sum = -y_[r];
      for (int c = 0; c < n_; ++c) sum += M_[r * n_ + c] * phi[c];
      residuals[r] = sum;
    }
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      for (std::size_t k = 0; k < M_.size(); ++k) jacobians[0][k] = M_[k];
    }
    return true;
  }

 private:
  const std::vector<double>& M_;
  const std::vector<double>& y_;
  int n_;
};

ceres::Solver::Options solverOptions() {
  ceres::Solver::Options options;
  // QR of the Jacobian: no normal equations are formed a second time.
  options.linear_solver_type = ceres::DENSE_QR;
  // The problem is linear: let the first Levenberg–Marquardt step be the Gauss–Newton step.
  options.initial_trust_region_radius = 1e16;
  options.num_threads = 1;  // one thread per solve: the callers parallelise across solves
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  options.logging_type = ceres::SILENT;
  return options;
}

}  // namespace

LinearSolve solveLinear(const std::vector<double>& M, const std::vector<double>& y, int N,
                        bool with_covariance, const std::string& what) {
  LinearSolve out;
  out.phi.assign(N, 0.0);
  ceres::Problem problem;
  problem.AddResidualBlock(new LinearCost(M, y, N), nullptr, out.phi.data());
  ceres::Solver::Summary summary;
  ceres::Solve(solverOptions(), &problem, &summary);
  if (summary.termination_type != ceres::CONVERGENCE || !summary.IsSolutionUsable()) {
    throw Error("Ceres did not converge on " + what + ": " + summary.message);
  }
  if (with_covariance) {
    ceres::Covariance::Options options;
    options.algorithm_type = ceres::DENSE_SVD;
    options.num_threads = 1;
    ceres::Covariance covariance(options);
    const double* block = out.phi.data();
    const std::vector<std::pair<const double*, const double*>> blocks = {{block, block}};
    out.unit_covariance.assign(static_cast<std::size_t>(N) * N, 0.0);
    if (!covariance.Compute(blocks, &problem) ||
        !covariance.GetCovarianceBlock(block, block, out.unit_covariance.data())) {
      throw Error("Ceres covariance failed on " + what + " (rank-deficient data?)");
    }
  }
  return out;
}

}  // namespace gtbake
