// The simultaneous (max-t) threshold of a band estimated from replicates (docs/fit.md §5).
//
// A band SE_j at m points, estimated from n independent units (scenes) with n − 1 degrees of
// freedom, is scored by the largest |Δ_j| / SE_j over the points. Under "no difference" that
// maximum is not Student-t: it is the maximum of m correlated t statistics, so the pointwise
// quantile t_{0.975, n−1} raises a false alarm far more often than 5 %. The threshold here is the
// level-quantile of
//   T = max_j √n |ȳ_j| / s_j,   y_1..y_n iid N(0, Σ),
// where Σ is the covariance of the replicates over the points (its correlation is all that
// matters: T is invariant to each point's scale) and ȳ_j, s_j are the mean and standard deviation
// of n simulated units (n − 1 degrees of freedom, estimated per point as the band is). With the
// replicates' deviations d = U S Vᵀ (rank r), y = ξ S Vᵀ with ξ an n × r matrix of iid N(0, 1), so
// a draw costs O(m r²), not O(m n²). Draws come from CounterRng(seed, draw), so the threshold is a
// pure function of (replicates, n, scored, rule) on any thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace gtbake {

// The name of the rule, as fit.json and validate_gtso.json report it.
inline constexpr const char* kMaxTMethod =
    "simultaneous max-t over the scored points, by simulation from the replicates' covariance "
    "with n - 1 degrees of freedom";

struct MaxTRule {
  double level = 0.95;     // simultaneous coverage (the false-alarm rate is 1 − level)
  int draws = 4000;        // simulated maxima (the quantile's rate error is ~√(0.05·0.95/draws))
  std::uint64_t seed = 1;  // CounterRng seed
};

// [replicate][point]: e.g. the delete-one-scene refits' curves on a grid, or per-scene values.
using ReplicateMatrix = std::vector<std::vector<double>>;

// The threshold for max_j |Δ_j| / SE_j over the points with scored[j] != 0 (all points when
// `scored` is empty). n ≥ 2 is the number of independent units behind the band; the replicates'
// rank must be below n. Throws gtbake::Error on a ragged matrix or no scored point with spread.
double maxTThreshold(const ReplicateMatrix& replicates, std::size_t n,
                     const std::vector<char>& scored, const MaxTRule& rule = {});

// The rule's simulated maxima, ascending (maxTThreshold is their level-quantile); the same
// preconditions and errors.
std::vector<double> simulatedMaxT(const ReplicateMatrix& replicates, std::size_t n,
                                  const std::vector<char>& scored, const MaxTRule& rule = {});
// The level-quantile of ascending simulated maxima.
double maxTQuantile(const std::vector<double>& maxima, double level);
// The fraction of simulated maxima above `threshold`: the false-alarm rate of a rule using it.
double maxTExceedance(const std::vector<double>& maxima, double threshold);

// Two independent standard normals from CounterRng(seed, stream) at (index, block) (Box–Muller).
void normalPair(std::uint64_t seed, std::uint64_t stream, std::uint64_t index, double out[2]);

}  // namespace gtbake
