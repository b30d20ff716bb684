#include "fit/simultaneous_band.h"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/math_constants.h"
#include "common/rng.h"

namespace gtbake {

namespace {

// Eigenvalues of the replicates' Gram matrix below this fraction of the largest are rounding
// (the deviations sum to zero, so one always is).
constexpr double kRankTolerance = 1e-12;

// W (points × r): the scored points' deviations projected on the Gram matrix's eigenvectors, so
// that y = ξ Wᵀ has the replicates' covariance up to a common scale.
Eigen::MatrixXd projectedDeviations(const ReplicateMatrix& replicates,
                                    const std::vector<char>& scored) {
  const std::size_t rows = replicates.size();
  const std::size_t m = replicates.front().size();
  std::vector<std::size_t> cols;
  for (std::size_t j = 0; j < m; ++j) {
    if (scored.empty() || scored[j] != 0) cols.push_back(j);
  }
  Eigen::MatrixXd d(rows, cols.size());
  for (std::size_t c = 0; c < cols.size(); ++c) {
    double sum = 0.0;
    for (std::size_t s = 0; s < rows; ++s) sum += replicates[s][cols[c]];
    const double mean = sum / static_cast<double>(rows);
    for (std::size_t s = 0; s < rows; ++s) d(s, c) = replicates[s][cols[c]] - mean;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(d * d.transpose());
  const Eigen::VectorXd& values = eig.eigenvalues();  // ascending
  const double largest = values.size() > 0 ? values(values.size() - 1) : 0.0;
  if (!(largest > 0.0)) throw Error("max-t threshold: the replicates do not vary at any point");
  int r = 0;
  while (r < values.size() && values(values.size() - 1 - r) > kRankTolerance * largest) ++r;
  return d.transpose() * eig.eigenvectors().rightCols(r);
}

// Draws simulated per block: a block's means and variances at every point are two matrix
// products, (points × r)(r × block) and (points × r(r+1)/2)(r(r+1)/2 × block).
constexpr std::size_t kBlock = 32;

// The per-point products W_jk W_jl (k ≤ l, doubled off the diagonal), so that the variance of
// ξ Wᵀ at point j under a covariance C is their dot product with C's upper triangle.
Eigen::MatrixXd quadraticTerms(const Eigen::MatrixXd& W) {
  const Eigen::Index r = W.cols();
  Eigen::MatrixXd Q(W.rows(), r * (r + 1) / 2);
  Eigen::Index q = 0;
  for (Eigen::Index k = 0; k < r; ++k) {
    for (Eigen::Index l = k; l < r; ++l)
      Q.col(q++) = (k == l ? 1.0 : 2.0) * W.col(k).cwiseProduct(W.col(l));
  }
  return Q;
}

// Draw `draw`'s mean (r) and covariance upper triangle (r(r+1)/2) of n iid N(0, I_r) units.
void drawMoments(std::size_t n, Eigen::Index r, const MaxTRule& rule, std::uint64_t draw,
                 Eigen::Ref<Eigen::VectorXd> mean, Eigen::Ref<Eigen::VectorXd> upper) {
  Eigen::MatrixXd xi(n, r);
  for (Eigen::Index k = 0; k < xi.size(); k += 2) {
    double z[2];
    normalPair(rule.seed, draw, static_cast<std::uint64_t>(k / 2), z);
    xi.data()[k] = z[0];
    if (k + 1 < xi.size()) xi.data()[k + 1] = z[1];
  }
  mean = xi.colwise().mean().transpose();
  const Eigen::MatrixXd centred = xi.rowwise() - mean.transpose();
  const Eigen::MatrixXd C = centred.transpose() * centred / static_cast<double>(n - 1);
  Eigen::Index q = 0;
  for (Eigen::Index k = 0; k < r; ++k) {
    for (Eigen::Index l = k; l < r; ++l) upper(q++) = C(k, l);
  }
}

// The simulated maxima of √n |ȳ_j| / s_j for draws [first, first + count).
void simulatedMaxima(const Eigen::MatrixXd& W, const Eigen::MatrixXd& Q, std::size_t n,
                     const MaxTRule& rule, std::size_t first, std::size_t count, double* out) {
  Eigen::MatrixXd means(W.cols(), count), uppers(Q.cols(), count);
  for (std::size_t b = 0; b < count; ++b) {
    drawMoments(n, W.cols(), rule, first + b, means.col(b), uppers.col(b));
  }
  const Eigen::MatrixXd num = W * means;
  const Eigen::MatrixXd var = Q * uppers;
  for (std::size_t b = 0; b < count; ++b) {
    double best = 0.0;
    for (Eigen::Index j = 0; j < W.rows(); ++j) {
      if (var(j, b) > 0.0) best = std::max(best, num(j, b) * num(j, b) / var(j, b));
    }
    out[b] = std::sqrt(static_cast<double>(n) * best);
  }
}

}  // namespace

void normalPair(std::uint64_t seed, std::uint64_t stream, std::uint64_t index, double out[2]) {
  const auto w = CounterRng(seed, stream).words(index, 0);
  // 53-bit uniforms in (0, 1] and [0, 1).
  const double u1 =
      (static_cast<double>((std::uint64_t{w[0]} << 21) ^ (w[1] >> 11)) + 1.0) / 9007199254740992.0;
  const double u2 =
      static_cast<double>((std::uint64_t{w[2]} << 21) ^ (w[3] >> 11)) / 9007199254740992.0;
  const double radius = std::sqrt(-2.0 * std::log(u1));
  out[0] = radius * std::cos(2.0 * kPi * u2);
  out[1] = radius * std::sin(2.0 * kPi * u2);
}

std::vector<double> simulatedMaxT(const ReplicateMatrix& replicates, std::size_t n,
                                  const std::vector<char>& scored, const MaxTRule& rule) {
  if (replicates.size() < 2 || n < 2) throw Error("max-t threshold: needs at least 2 replicates");
  for (const std::vector<double>& row : replicates) {
    if (row.size() != replicates.front().size()) throw Error("max-t threshold: ragged replicates");
  }
  if (!scored.empty() && scored.size() != replicates.front().size()) {
    throw Error("max-t threshold: the scored mask does not match the points");
  }
  if (rule.draws < 1 || !(rule.level > 0.0 && rule.level < 1.0)) {
    throw Error("max-t threshold: bad level or draw count");
  }
  const Eigen::MatrixXd W = projectedDeviations(replicates, scored);
  if (static_cast<std::size_t>(W.cols()) >= n) {
    throw Error("max-t threshold: the replicates' rank is not below n");
  }
  const Eigen::MatrixXd Q = quadraticTerms(W);
  std::vector<double> maxima(static_cast<std::size_t>(rule.draws));
  tbb::parallel_for(std::size_t{0}, (maxima.size() + kBlock - 1) / kBlock, [&](std::size_t b) {
    const std::size_t first = b * kBlock;
    simulatedMaxima(W, Q, n, rule, first, std::min(kBlock, maxima.size() - first), &maxima[first]);
  });
  std::sort(maxima.begin(), maxima.end());
  return maxima;
}

double maxTQuantile(const std::vector<double>& maxima, double level) {
  const auto at = static_cast<std::size_t>(std::ceil(level * maxima.size())) - 1;
  return maxima[std::min(at, maxima.size() - 1)];
}

double maxTExceedance(const std::vector<double>& maxima, double threshold) {
  const auto above = maxima.end() - std::upper_bound(maxima.begin(), maxima.end(), threshold);
  return static_cast<double>(above) / static_cast<double>(maxima.size());
}

double maxTThreshold(const ReplicateMatrix& replicates, std::size_t n,
                     const std::vector<char>& scored, const MaxTRule& rule) {
  return maxTQuantile(simulatedMaxT(replicates, n, scored, rule), rule.level);
}

}  // namespace gtbake
