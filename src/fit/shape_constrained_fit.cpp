#include "fit/shape_constrained_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"

namespace gtbake {

namespace {

using Vector4 = Eigen::Vector4d;
using Matrix4 = Eigen::Matrix4d;

// Active-set iterations before giving up (each adds or drops one constraint; at most 4 are active).
constexpr int kMaxIterations = 1000;
// A step shorter than this (relative to |φ|) is a zero step: the working set's optimum is reached.
constexpr double kStepTolerance = 1e-13;
// Multipliers above −kMultiplierTolerance count as ≥ 0 (the objective is a mean square / 2, its
// gradient O(1); rounding leaves ~1e-16).
constexpr double kMultiplierTolerance = 1e-14;

// k = T φ + t0 with φ = (a1, a0, b1, b0): c1 = b1 − a1, c0 = 1 − a0 + b0.
Eigen::Matrix<double, 6, 4> eliminationMap() {
  Eigen::Matrix<double, 6, 4> T = Eigen::Matrix<double, 6, 4>::Zero();
  T(0, 0) = T(1, 1) = T(2, 2) = T(3, 3) = 1.0;
  T(4, 0) = -1.0;
  T(4, 2) = 1.0;
  T(5, 1) = -1.0;
  T(5, 3) = 1.0;
  return T;
}

MultiBounceCoeffs coefficientsOf(const Vector4& phi) {
  return {phi[0], phi[1], phi[2], phi[3], phi[2] - phi[0], 1.0 - phi[1] + phi[3]};
}

// The inequalities c·φ ≥ d: dG/dÂ ≥ 0 at every node and G ≥ 0 at every node but Â = 0 (where
// G = 0 identically), at both ends of ρ.
struct Inequalities {
  std::vector<Vector4> c;
  std::vector<double> d;
};

Inequalities shapeInequalities(int nodes) {
  const Eigen::Matrix<double, 6, 4> T = eliminationMap();
  const Eigen::Matrix<double, 6, 1> t0 =
      (Eigen::Matrix<double, 6, 1>() << 0, 0, 0, 0, 0, 1).finished();
  Inequalities out;
  const auto add = [&](const MultiBounceCoeffs& g) {
    const Eigen::Map<const Eigen::Matrix<double, 6, 1>> row(g.data());
    out.c.push_back(T.transpose() * row);
    out.d.push_back(-row.dot(t0));
  };
  for (int i = 0; i < nodes; ++i) {
    const double A = shapeGridA(i, nodes);
    for (double rho : kShapeRhos) {
      add(slopeGradient(A, rho));
      if (i > 0) add(multiBounceGradient(A, rho));
    }
  }
  return out;
}

// The step p minimising the quadratic from φ with the working set's constraints held as
// equalities, and their multipliers λ (gradient = Σ λ_i c_i at the step's end).
struct Step {
  Vector4 p;
  std::vector<double> lambda;
};

Step equalityStep(const Matrix4& Q, const Vector4& gradient, const Inequalities& in,
                  const std::vector<std::size_t>& working) {
  const Eigen::Index w = static_cast<Eigen::Index>(working.size());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(4 + w, 4 + w);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(4 + w);
  K.topLeftCorner(4, 4) = Q;
  rhs.head(4) = -gradient;
  for (Eigen::Index r = 0; r < w; ++r) {
    const Vector4& c = in.c[working[static_cast<std::size_t>(r)]];
    K.block(0, 4 + r, 4, 1) = -c;
    K.block(4 + r, 0, 1, 4) = c.transpose();
  }
  const Eigen::VectorXd x = K.fullPivLu().solve(rhs);
  Step s;
  s.p = x.head(4);
  for (Eigen::Index r = 0; r < w; ++r) s.lambda.push_back(x[4 + r]);
  return s;
}

}  // namespace

double ProfileObjective::value(const MultiBounceCoeffs& k) const {
  double v = 0.0;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) v += 0.5 * k[r] * H[6 * r + c] * k[c];
    v -= m[r] * k[r];
  }
  return v;
}

ProfileObjective profileObjective(const NormalEquations& sums, const std::vector<double>& albedos) {
  const long double total = sums.weight * static_cast<long double>(albedos.size());
  ProfileObjective out;
  // Index 2q + e: q ∈ {a, b, c}, e = 0 the slope in ρ (factor ρ), e = 1 the intercept (factor 1).
  for (std::size_t j = 0; j < albedos.size(); ++j) {
    const long double r[2] = {albedos[j], 1.0L};
    for (int q = 0; q < 3; ++q) {
      for (int e = 0; e < 2; ++e) {
        out.m[2 * q + e] += static_cast<double>(r[e] * sums.moment[j][q] / total);
        for (int q2 = 0; q2 < 3; ++q2) {
          for (int e2 = 0; e2 < 2; ++e2) {
            out.H[6 * (2 * q + e) + 2 * q2 + e2] +=
                static_cast<double>(r[e] * r[e2] * sums.gram[3 * q + q2] / total);
          }
        }
      }
    }
  }
  return out;
}

MultiBounceCoeffs solveShapeConstrained(const ProfileObjective& objective, int nodes) {
  const Eigen::Matrix<double, 6, 4> T = eliminationMap();
  const Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> H(objective.H.data());
  const Eigen::Map<const Eigen::Matrix<double, 6, 1>> m(objective.m.data());
  const Eigen::Matrix<double, 6, 1> t0 =
      (Eigen::Matrix<double, 6, 1>() << 0, 0, 0, 0, 0, 1).finished();
  const Matrix4 Q = T.transpose() * H * T;
  const Vector4 q = T.transpose() * (m - H * t0);
  const Inequalities in = shapeInequalities(nodes);
  Vector4 phi = Vector4::Zero();  // G = Â: feasible, no constraint active
  std::vector<std::size_t> working;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    const Step s = equalityStep(Q, Q * phi - q, in, working);
    if (s.p.lpNorm<Eigen::Infinity>() <= kStepTolerance * (1.0 + phi.lpNorm<Eigen::Infinity>())) {
      const auto most_negative = std::min_element(s.lambda.begin(), s.lambda.end());
      if (most_negative == s.lambda.end() || *most_negative >= -kMultiplierTolerance)
        return coefficientsOf(phi);
      working.erase(working.begin() + (most_negative - s.lambda.begin()));
      continue;
    }
    double alpha = 1.0;
    std::size_t blocking = in.c.size();
    for (std::size_t i = 0; i < in.c.size(); ++i) {
      const double along = in.c[i].dot(s.p);
      if (along >= -kStepTolerance * s.p.norm() * in.c[i].norm() ||
          std::find(working.begin(), working.end(), i) != working.end())
        continue;
      const double reach = std::max(0.0, in.c[i].dot(phi) - in.d[i]) / -along;
      if (reach < alpha) {
        alpha = reach;
        blocking = i;
      }
    }
    phi += alpha * s.p;
    if (blocking < in.c.size()) working.push_back(blocking);
  }
  throw Error("the shape-constrained profile fit did not converge in " +
              std::to_string(kMaxIterations) + " active-set iterations");
}

}  // namespace gtbake
