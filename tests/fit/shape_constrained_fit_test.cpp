// The shape-constrained profile fit (docs/profiles.md §7) against independent references: exact
// recovery of known constrained coefficients, the equality-only solution of a raw-point KKT solve,
// a monotone fit of decreasing data that touches its constraint, and a brute-force grid search
// over the four free parameters.
#include "fit/shape_constrained_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <random>

#include "fit/profile_shape.h"

namespace gtbake {
namespace {

const std::vector<double> kAlbedos = {0.1, 0.3, 0.5, 0.7, 0.9};
constexpr int kPoints = 400;

double pointA(int i) {
  return (i + 0.5) / kPoints;
}

// Unit-weight sums of G(A_i, ρ_j) = target(A_i, ρ_j) (+ noise of SD sigma).
NormalEquations sumsOf(const std::function<double(double, double)>& target, double sigma = 0.0) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<double> A(kPoints), w(kPoints, 1.0);
  std::vector<std::vector<double>> G(kAlbedos.size(), std::vector<double>(kPoints));
  for (int i = 0; i < kPoints; ++i) {
    A[i] = pointA(i);
    for (std::size_t j = 0; j < kAlbedos.size(); ++j) {
      G[j][i] = target(A[i], kAlbedos[j]) + (sigma > 0.0 ? noise(rng) : 0.0);
    }
  }
  std::vector<const double*> columns;
  for (const auto& g : G) columns.push_back(g.data());
  NormalEquations sums;
  accumulate(sums, w.data(), A.data(), columns, kPoints);
  return sums;
}

// A monotone profile with G(1, ρ) = 1 and no inequality active (dG/dA > 0.2 everywhere).
constexpr MultiBounceCoeffs kInterior = {0.4, 0.3, 0.9, 1.2, 0.5, 1.9};

TEST(ShapeConstrainedFit, RecoversKnownConstrainedCoefficients) {
  ASSERT_TRUE(shapeChecks(kInterior).pass());
  ASSERT_GT(shapeChecks(kInterior).min_slope, 0.2);
  const auto law = [](double A, double rho) { return evalMultiBounce(kInterior, A, rho); };
  const MultiBounceCoeffs k = solveShapeConstrained(profileObjective(sumsOf(law), kAlbedos));
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(k[i], kInterior[i], 1e-9) << kCoeffNames[i];
}

// With no inequality active the solution is the equality-constrained least squares over the raw
// points: a 6 + 2 KKT system built here from the design rows g(A, ρ), not from the sums.
TEST(ShapeConstrainedFit, InteriorOptimumIsTheEqualityConstrainedLeastSquares) {
  const double sigma = 0.02;
  const auto law = [](double A, double rho) { return evalMultiBounce(kInterior, A, rho); };
  const MultiBounceCoeffs k = solveShapeConstrained(profileObjective(sumsOf(law, sigma), kAlbedos));
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, sigma);
  Eigen::Matrix<double, 8, 8> K = Eigen::Matrix<double, 8, 8>::Zero();
  Eigen::Matrix<double, 8, 1> rhs = Eigen::Matrix<double, 8, 1>::Zero();
  for (int i = 0; i < kPoints; ++i) {  // the same noise draws, in the same order, as sumsOf
    for (double rho : kAlbedos) {
      const MultiBounceCoeffs g = multiBounceGradient(pointA(i), rho);
      const Eigen::Map<const Eigen::Matrix<double, 6, 1>> x(g.data());
      K.topLeftCorner<6, 6>() += x * x.transpose();
      rhs.head<6>() += x * (law(pointA(i), rho) + noise(rng));
    }
  }
  K.block<2, 6>(6, 0) << 1, 0, -1, 0, 1, 0, 0, 1, 0, -1, 0, 1;  // a − b + c: slope 0, intercept 1
  K.block<6, 2>(0, 6) = K.block<2, 6>(6, 0).transpose();
  rhs[7] = 1.0;
  const Eigen::Matrix<double, 8, 1> x = K.fullPivLu().solve(rhs);
  ASSERT_GT(shapeChecks(k).min_slope, 0.1);  // interior indeed
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(k[i], x[i], 1e-9) << kCoeffNames[i];
}

TEST(ShapeConstrainedFit, DecreasingDataGiveAMonotoneFitOnItsConstraint) {
  const auto falling = [](double A, double rho) { return 1.2 - 0.5 * A + 0.1 * rho; };
  const MultiBounceCoeffs k = solveShapeConstrained(profileObjective(sumsOf(falling), kAlbedos));
  const ShapeChecks s = shapeChecks(k);
  EXPECT_TRUE(s.pass());
  EXPECT_NEAR(s.min_slope, 0.0, 1e-12);  // it touches dG/dA = 0
  // G(1, ρ) = 1 to rounding: a − b + c = 1 holds by construction.
  for (double rho : kShapeRhos) EXPECT_NEAR(evalMultiBounce(k, 1.0, rho), 1.0, 1e-15);
  EXPECT_LE(s.open_max_deviation, 1e-15);
}

// Brute force: a 4D grid of the free parameters (a1, a0, b1, b0) around the solution, each node
// feasible on the same constraint grid or discarded. The QP's objective is no worse than any
// feasible node's, and the best node is within the grid's resolution of it.
TEST(ShapeConstrainedFit, NoFeasibleGridPointBeatsTheSolution) {
  constexpr int kNodes = 51;
  const auto overshoot = [](double A, double rho) { return (1.25 - 0.2 * rho) * std::sqrt(A); };
  const ProfileObjective objective = profileObjective(sumsOf(overshoot, 0.01), kAlbedos);
  const MultiBounceCoeffs k = solveShapeConstrained(objective, kNodes);
  ASSERT_TRUE(shapeChecks(k, kNodes).pass());
  ASSERT_NEAR(shapeChecks(k, kNodes).min_slope, 0.0, 1e-12);  // a constraint is active
  const double best_qp = objective.value(k);
  for (double h : {1e-2, 1e-4}) {
    double best_grid = INFINITY;
    constexpr int kSteps = 6;
    for (int u0 = -kSteps; u0 <= kSteps; ++u0) {
      for (int u1 = -kSteps; u1 <= kSteps; ++u1) {
        for (int u2 = -kSteps; u2 <= kSteps; ++u2) {
          for (int u3 = -kSteps; u3 <= kSteps; ++u3) {
            const double a1 = k[0] + h * u0, a0 = k[1] + h * u1, b1 = k[2] + h * u2,
                         b0 = k[3] + h * u3;
            const MultiBounceCoeffs c = {a1, a0, b1, b0, b1 - a1, 1.0 - a0 + b0};
            const ShapeChecks s = shapeChecks(c, kNodes);
            if (s.min_slope < 0.0 || s.min_G < 0.0) continue;
            best_grid = std::min(best_grid, objective.value(c));
          }
        }
      }
    }
    EXPECT_GE(best_grid, best_qp - 1e-15) << h;
    EXPECT_LE(best_grid - best_qp, 1e-2 * h) << h;
  }
}

}  // namespace
}  // namespace gtbake
