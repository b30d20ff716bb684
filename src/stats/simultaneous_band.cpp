#include "stats/simultaneous_band.h"

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
                                    const std::vector<std::size_t>& cols) {
  const std::size_t rows = replicates.size();
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

// The simulated maxima of √n |ȳ_j| / s_j over each group's points for draws [first, first +
// count): out[b · groups + g]. `group[j]` is the group of W's row j.
void simulatedMaxima(const Eigen::MatrixXd& W, const Eigen::MatrixXd& Q, std::size_t n,
                     const MaxTRule& rule, const std::vector<std::size_t>& group,
                     std::size_t groups, std::size_t first, std::size_t count, double* out) {
  Eigen::MatrixXd means(W.cols(), count), uppers(Q.cols(), count);
  for (std::size_t b = 0; b < count; ++b) {
    drawMoments(n, W.cols(), rule, first + b, means.col(b), uppers.col(b));
  }
  const Eigen::MatrixXd num = W * means;
  const Eigen::MatrixXd var = Q * uppers;
  std::vector<double> best(groups);
  for (std::size_t b = 0; b < count; ++b) {
    std::fill(best.begin(), best.end(), 0.0);
    for (Eigen::Index j = 0; j < W.rows(); ++j) {
      double& g = best[group[static_cast<std::size_t>(j)]];
      if (var(j, b) > 0.0) g = std::max(g, num(j, b) * num(j, b) / var(j, b));
    }
    for (std::size_t g = 0; g < groups; ++g) {
      out[b * groups + g] = std::sqrt(static_cast<double>(n) * best[g]);
    }
  }
}

// Checks the arguments of a simulation: replicates, unit count, the per-point groups, the rule.
void checkSimulation(const ReplicateMatrix& replicates, std::size_t n,
                     const std::vector<int>& group_of, std::size_t groups, const MaxTRule& rule) {
  if (replicates.size() < 2 || n < 2) throw Error("max-t threshold: needs at least 2 replicates");
  for (const std::vector<double>& row : replicates) {
    if (row.size() != replicates.front().size()) throw Error("max-t threshold: ragged replicates");
  }
  if (group_of.size() != replicates.front().size()) {
    throw Error("max-t threshold: the scored mask does not match the points");
  }
  for (int g : group_of) {
    if (g >= static_cast<int>(groups))
      throw Error("max-t threshold: a point's group is out of range");
  }
  if (rule.draws < 1 || !(rule.level > 0.0 && rule.level < 1.0)) {
    throw Error("max-t threshold: bad level or draw count");
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

std::vector<double> simulatedGroupMaxT(const ReplicateMatrix& replicates, std::size_t n,
                                       const std::vector<int>& group_of, std::size_t groups,
                                       const MaxTRule& rule) {
  checkSimulation(replicates, n, group_of, groups, rule);
  std::vector<std::size_t> cols, group;
  for (std::size_t j = 0; j < group_of.size(); ++j) {
    if (group_of[j] < 0) continue;
    cols.push_back(j);
    group.push_back(static_cast<std::size_t>(group_of[j]));
  }
  const Eigen::MatrixXd W = projectedDeviations(replicates, cols);
  if (static_cast<std::size_t>(W.cols()) >= n) {
    throw Error("max-t threshold: the replicates' rank is not below n");
  }
  const Eigen::MatrixXd Q = quadraticTerms(W);
  const auto draws = static_cast<std::size_t>(rule.draws);
  std::vector<double> maxima(draws * groups);
  tbb::parallel_for(std::size_t{0}, (draws + kBlock - 1) / kBlock, [&](std::size_t b) {
    const std::size_t first = b * kBlock;
    simulatedMaxima(W, Q, n, rule, group, groups, first, std::min(kBlock, draws - first),
                    &maxima[first * groups]);
  });
  return maxima;
}

std::vector<double> overallMaxima(const std::vector<double>& group_maxima, std::size_t groups) {
  std::vector<double> out(group_maxima.size() / groups, 0.0);
  for (std::size_t d = 0; d < out.size(); ++d) {
    for (std::size_t g = 0; g < groups; ++g)
      out[d] = std::max(out[d], group_maxima[d * groups + g]);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<double> jointGroupThresholds(const std::vector<double>& group_maxima,
                                         std::size_t groups, double level) {
  const std::size_t draws = group_maxima.size() / groups;
  std::vector<std::vector<double>> sorted(groups);
  for (std::size_t g = 0; g < groups; ++g) {
    for (std::size_t d = 0; d < draws; ++d) sorted[g].push_back(group_maxima[d * groups + g]);
    std::sort(sorted[g].begin(), sorted[g].end());
  }
  // Draws with some group above its threshold at the common rank k; non-increasing in k.
  const auto exceeding = [&](std::size_t k) {
    std::size_t count = 0;
    for (std::size_t d = 0; d < draws; ++d) {
      bool above = false;
      for (std::size_t g = 0; g < groups && !above; ++g) {
        above = group_maxima[d * groups + g] > sorted[g][k];
      }
      count += above ? 1 : 0;
    }
    return count;
  };
  const double allowed = (1.0 - level) * static_cast<double>(draws);
  std::size_t lo = 0, hi = draws - 1;  // exceeding(draws − 1) = 0 ≤ allowed
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (static_cast<double>(exceeding(mid)) <= allowed) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  std::vector<double> out(groups);
  for (std::size_t g = 0; g < groups; ++g) out[g] = sorted[g][lo];
  return out;
}

std::vector<double> simulatedMaxT(const ReplicateMatrix& replicates, std::size_t n,
                                  const std::vector<char>& scored, const MaxTRule& rule) {
  std::vector<int> group_of(replicates.empty() ? 0 : replicates.front().size(), 0);
  if (!scored.empty()) {
    group_of.assign(scored.size(), 0);
    for (std::size_t j = 0; j < scored.size(); ++j) group_of[j] = scored[j] != 0 ? 0 : -1;
  }
  return overallMaxima(simulatedGroupMaxT(replicates, n, group_of, 1, rule), 1);
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
