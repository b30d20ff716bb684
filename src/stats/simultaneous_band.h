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
// The same simulation with the points split into groups (e.g. ranges of A): group_of[j] is point
// j's group in [0, groups), or −1 for a point not scored. Returns each draw's maximum over each
// group's points, [draw · groups + group]; the maximum over all groups is simulatedMaxT's draw.
std::vector<double> simulatedGroupMaxT(const ReplicateMatrix& replicates, std::size_t n,
                                       const std::vector<int>& group_of, std::size_t groups,
                                       const MaxTRule& rule);
// Each draw's maximum over every group, ascending (simulatedMaxT's maxima).
std::vector<double> overallMaxima(const std::vector<double>& group_maxima, std::size_t groups);
// Per-group thresholds c_g, simultaneous over the groups and over every point within each: c_g is
// group g's simulated maxima at one common rank k, the smallest k at which at most a share
// 1 − level of the draws has any group above its threshold. So a rule "some group's largest
// |Δ| / SE exceeds its c_g" raises a false alarm at most 1 − level of the time, and each group's
// own false-alarm rate is the same tail share (between (1 − level)/groups and 1 − level).
std::vector<double> jointGroupThresholds(const std::vector<double>& group_maxima,
                                         std::size_t groups, double level);
// The level-quantile of ascending simulated maxima.
double maxTQuantile(const std::vector<double>& maxima, double level);
// The fraction of simulated maxima above `threshold`: the false-alarm rate of a rule using it.
double maxTExceedance(const std::vector<double>& maxima, double threshold);

// Two independent standard normals from CounterRng(seed, stream) at (index, block) (Box–Muller).
void normalPair(std::uint64_t seed, std::uint64_t stream, std::uint64_t index, double out[2]);

}  // namespace gtbake
