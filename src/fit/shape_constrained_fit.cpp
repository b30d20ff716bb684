#include "fit/shape_constrained_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

namespace gtbake {

namespace {

using Vector4 = Eigen::Vector4d;
using Matrix4 = Eigen::Matrix4d;

// Active-set iterations before giving up, per constraint: where the touching point of dG/dÂ = 0
// slides along the grid, each node it passes costs an add and a drop (measured: up to ~1100
// iterations for 4004 constraints on the tune tests' data), so the bound scales with the grid.
constexpr int kIterationsPerConstraint = 2;
// A step shorter than this (relative to |φ|) is a zero step: the working set's optimum is reached.
constexpr double kStepTolerance = 1e-13;
// Multipliers above −kMultiplierTolerance count as ≥ 0 (the objective is a mean square / 2, its
// gradient O(1); rounding leaves ~1e-16).
constexpr double kMultiplierTolerance = 1e-14;
// Rows whose QR pivot falls below this (relative) add no rank: the constraint is a combination of
// the working set's (adjacent grid nodes are close to parallel, not dependent, far above it).
constexpr double kIndependenceTolerance = 1e-10;
// Reaches within this of the smallest count as reached together (Bland's rule picks among them).
constexpr double kTieTolerance = 1e-15;

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
// equalities, and their multipliers λ (gradient = Σ λ_i c_i at the step's end). Null-space form:
// the working set is kept linearly independent (at most 4 rows), so p = −Z (ZᵀQZ)⁻¹ Zᵀg with Z an
// orthonormal basis of the rows' null space, and λ solves Wᵀλ = Qp + g (least squares, exact when
// consistent).
struct Step {
  Vector4 p;
  std::vector<double> lambda;
};

Eigen::MatrixXd workingRows(const Inequalities& in, const std::vector<std::size_t>& working) {
  Eigen::MatrixXd W(static_cast<Eigen::Index>(working.size()), 4);
  for (std::size_t r = 0; r < working.size(); ++r) {
    W.row(static_cast<Eigen::Index>(r)) = in.c[working[r]].transpose();
  }
  return W;
}

Step equalityStep(const Matrix4& Q, const Vector4& gradient, const Inequalities& in,
                  const std::vector<std::size_t>& working) {
  Step s;
  const Eigen::MatrixXd W = workingRows(in, working);
  const Eigen::Index w = W.rows();
  if (w == 0) {
    s.p = -Q.ldlt().solve(gradient);
    return s;
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(W.transpose());
  const Eigen::MatrixXd basis = qr.householderQ() * Eigen::MatrixXd::Identity(4, 4);
  s.p.setZero();
  if (w < 4) {
    const Eigen::MatrixXd Z = basis.rightCols(4 - w);
    const Eigen::MatrixXd reduced = Z.transpose() * Q * Z;
    s.p = -Z * reduced.ldlt().solve(Z.transpose() * gradient);
  }
  const Eigen::VectorXd lambda = W.transpose().colPivHouseholderQr().solve(Q * s.p + gradient);
  s.lambda.assign(lambda.data(), lambda.data() + w);
  return s;
}

// Whether constraint i is linearly independent of the working set (relative tolerance): only
// such a constraint can join it. A dependent one is parallel to the step within rounding.
bool independentOf(const Inequalities& in, const std::vector<std::size_t>& working, std::size_t i) {
  if (working.size() >= 4) return false;
  std::vector<std::size_t> with = working;
  with.push_back(i);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(workingRows(in, with).transpose());
  qr.setThreshold(kIndependenceTolerance);
  return qr.rank() == static_cast<Eigen::Index>(with.size());
}

// The blocking constraint of a step from φ along p: the smallest reach α ∈ [0, 1) at which a
// constraint outside the working set would be violated, ties (within rounding) to the smallest
// index (Bland's rule, which rules out cycling through degenerate zero steps); constraints that
// are dependent on the working set are passed over. Returns in.c.size() when nothing blocks.
std::size_t blockingConstraint(const Inequalities& in, const std::vector<std::size_t>& working,
                               const Vector4& phi, const Vector4& p, double* alpha) {
  std::vector<std::pair<double, std::size_t>> reaches;
  for (std::size_t i = 0; i < in.c.size(); ++i) {
    const double along = in.c[i].dot(p);
    if (along >= -kStepTolerance * p.norm() * in.c[i].norm() ||
        std::find(working.begin(), working.end(), i) != working.end())
      continue;
    const double reach = std::max(0.0, in.c[i].dot(phi) - in.d[i]) / -along;
    if (reach < 1.0) reaches.emplace_back(reach, i);
  }
  std::sort(reaches.begin(), reaches.end());
  for (std::size_t k = 0; k < reaches.size(); ++k) {
    // Bland: among the constraints reached first (within rounding), the smallest index.
    std::size_t best = reaches.size();
    for (std::size_t t = k;
         t < reaches.size() && reaches[t].first <= reaches[k].first + kTieTolerance; ++t) {
      if ((best == reaches.size() || reaches[t].second < reaches[best].second) &&
          independentOf(in, working, reaches[t].second))
        best = t;
    }
    if (best < reaches.size()) {
      *alpha = reaches[k].first;
      return reaches[best].second;
    }
  }
  *alpha = 1.0;
  return in.c.size();
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

MultiBounceCoeffs solveShapeConstrained(const ProfileObjective& objective, int nodes,
                                        bool* converged) {
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
  const int max_iterations = kIterationsPerConstraint * static_cast<int>(in.c.size());
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    const Step s = equalityStep(Q, Q * phi - q, in, working);
    if (s.p.lpNorm<Eigen::Infinity>() <= kStepTolerance * (1.0 + phi.lpNorm<Eigen::Infinity>())) {
      // Bland: drop the negative multiplier of the smallest constraint index.
      std::size_t drop = working.size();
      for (std::size_t r = 0; r < working.size(); ++r) {
        if (s.lambda[r] < -kMultiplierTolerance &&
            (drop == working.size() || working[r] < working[drop]))
          drop = r;
      }
      if (drop == working.size()) {
        if (converged != nullptr) *converged = true;
        return coefficientsOf(phi);
      }
      working.erase(working.begin() + static_cast<std::ptrdiff_t>(drop));
      continue;
    }
    double alpha = 1.0;
    const std::size_t blocking = blockingConstraint(in, working, phi, s.p, &alpha);

    phi += alpha * s.p;
    if (blocking < in.c.size()) working.push_back(blocking);
  }
  // Every iterate is feasible and no step raises the objective, so the last one is a profile
  // that passes the shape checks, optimal or within the last steps of the optimum; degenerate
  // grids (many near-parallel constraints touching at once) can make the method stall.
  if (converged != nullptr) *converged = false;
  return coefficientsOf(phi);
}

}  // namespace gtbake
