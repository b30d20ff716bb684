// The max-t threshold against closed forms: one point (and perfectly correlated points) give
// Student's t quantile, independent points give Šidák's, and it ignores each point's scale.
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "common/threads.h"
#include "fit/scene_jackknife.h"
#include "stats/simultaneous_band.h"

namespace gtbake {
namespace {

constexpr MaxTRule kRule{0.95, 20000, 7};
// The quantile's Monte Carlo SD at 20000 draws is ~0.017 for 6 degrees of freedom (binomial SD of
// the rate, √(0.05 · 0.95 / 20000), over the density of |t_6| at 2.447, 0.092); 3 SD.
constexpr double kTolerance = 0.05;

// n replicates of `cols` points: column c is `pattern(s, c)`.
template <typename F>
ReplicateMatrix matrix(std::size_t n, std::size_t cols, F&& pattern) {
  ReplicateMatrix out(n, std::vector<double>(cols));
  for (std::size_t s = 0; s < n; ++s) {
    for (std::size_t c = 0; c < cols; ++c) out[s][c] = pattern(s, c);
  }
  return out;
}

TEST(MaxTThreshold, OnePointIsStudentT) {
  for (std::size_t n : {4, 7, 12}) {
    const ReplicateMatrix r =
        matrix(n, 1, [](std::size_t s, std::size_t) { return std::sin(s + 1.0); });
    EXPECT_NEAR(maxTThreshold(r, n, {}, kRule), studentT975(n - 1), kTolerance * (n == 4 ? 2 : 1))
        << n;
  }
}

TEST(MaxTThreshold, PerfectlyCorrelatedPointsAreOnePointAtAnyScale) {
  const ReplicateMatrix r = matrix(7, 30, [](std::size_t s, std::size_t c) {
    return (c % 2 == 0 ? 1.0 : -3.0) * (c + 1.0) * std::cos(1.7 * s) + 5.0 * c;
  });
  EXPECT_NEAR(maxTThreshold(r, 7, {}, kRule), studentT975(6), kTolerance);
}

// Two uncorrelated points with many units: max of two independent |t_399| has the 95 % quantile
// t_{(1 + √0.95)/2, 399} = 2.245 (Šidák; z = 2.2365 plus the Cornish–Fisher term (z³ + z)/(4ν)).
TEST(MaxTThreshold, IndependentPointsAreSidak) {
  constexpr std::size_t n = 400;
  const ReplicateMatrix r = matrix(n, 2, [](std::size_t s, std::size_t c) {
    // Orthogonal ±1 patterns (Walsh functions of s).
    return c == 0 ? ((s % 2) ? 1.0 : -1.0) : ((s / 2) % 2 ? 1.0 : -1.0);
  });
  const double threshold = maxTThreshold(r, n, {}, kRule);
  EXPECT_NEAR(threshold, 2.245, kTolerance);
  EXPECT_GT(threshold, studentT975(n - 1) + 0.2);  // the pointwise rule is visibly too small
  // The pointwise rule on two independent points alarms 1 − 0.95² = 9.75 % of the time (binomial
  // SD 0.2 % at 20000 draws).
  const std::vector<double> maxima = simulatedMaxT(r, n, {}, kRule);
  EXPECT_NEAR(maxTExceedance(maxima, studentT975(n - 1)), 0.0975, 0.007);
  EXPECT_NEAR(maxTExceedance(maxima, threshold), 0.05, 1e-3);
  EXPECT_EQ(maxTQuantile(maxima, 0.95), threshold);
}

TEST(MaxTThreshold, MaskDropsPointsDeterministically) {
  const ReplicateMatrix r = matrix(7, 3, [](std::size_t s, std::size_t c) {
    return c == 2 ? 1.0 : std::sin((c + 1.0) * (s + 1.0));
  });
  const double all = maxTThreshold(r, 7, {1, 1, 0}, kRule);
  EXPECT_EQ(all, maxTThreshold(r, 7, {1, 1, 0}, kRule));
  EXPECT_NEAR(maxTThreshold(r, 7, {1, 0, 0}, kRule), studentT975(6), kTolerance);
  EXPECT_GT(all, studentT975(6) + 0.1);
  EXPECT_THROW(maxTThreshold(r, 7, {0, 0, 1}, kRule), Error);  // a constant point has no band
  EXPECT_THROW(maxTThreshold({{1.0, 2.0}, {1.0}}, 2, {}, kRule), Error);
  EXPECT_THROW(maxTThreshold(r, 7, {1}, kRule), Error);
}

// Each draw is a pure function of (seed, draw): the threshold is the same bits on 1 and 2 threads.
TEST(MaxTThreshold, SameBitsOnOneAndTwoThreads) {
  const ReplicateMatrix r = matrix(7, 500, [](std::size_t s, std::size_t c) {
    return std::sin(0.01 * c * (s + 1.0)) + 0.1 * std::cos(3.0 * s + c);
  });
  double t[2];
  for (int k = 0; k < 2; ++k) {
    ThreadLimit limit(k + 1);
    t[k] = maxTThreshold(r, 7, {}, {0.95, 2000, 3});
  }
  EXPECT_EQ(t[0], t[1]);
}

// Groups: each group's maximum in a draw is the overall simulation restricted to its points, the
// overall maximum is their largest, and the joint thresholds are simultaneous: on fresh draws
// (another seed) the share with some group above its threshold is 5 %, and each group's own
// share lies between 5 % / groups and 5 %.
TEST(MaxTGroups, GroupMaximaAreTheRestrictedSimulation) {
  const ReplicateMatrix r = matrix(9, 60, [](std::size_t s, std::size_t c) {
    return std::sin(0.05 * c * (s + 1.0)) + 0.2 * std::cos(2.0 * s + 0.3 * c);
  });
  std::vector<int> group(60);
  for (std::size_t c = 0; c < group.size(); ++c) group[c] = c < 5 ? -1 : static_cast<int>(c % 3);
  const MaxTRule rule{0.95, 500, 11};
  const std::vector<double> by_group = simulatedGroupMaxT(r, 9, group, 3, rule);
  ASSERT_EQ(by_group.size(), 500u * 3u);
  std::vector<char> scored(60, 0);
  for (std::size_t c = 5; c < scored.size(); ++c) scored[c] = 1;
  EXPECT_EQ(overallMaxima(by_group, 3), simulatedMaxT(r, 9, scored, rule));
  EXPECT_THROW(simulatedGroupMaxT(r, 9, group, 2, rule), Error);  // a group out of range
}

TEST(MaxTGroups, JointThresholdsAreSimultaneousOverTheGroups) {
  // Three groups of independent points (Šidák within each, independent across groups).
  const ReplicateMatrix r = matrix(12, 9, [](std::size_t s, std::size_t c) {
    return std::cos(1.7 * static_cast<double>(s * (c + 1)) + 0.4 * c);
  });
  std::vector<int> group(9);
  for (std::size_t c = 0; c < group.size(); ++c) group[c] = static_cast<int>(c / 3);
  const std::vector<double> thresholds =
      jointGroupThresholds(simulatedGroupMaxT(r, 12, group, 3, {0.95, 20000, 5}), 3, 0.95);
  const std::vector<double> fresh = simulatedGroupMaxT(r, 12, group, 3, {0.95, 20000, 6});
  std::size_t any = 0, each[3] = {0, 0, 0};
  for (std::size_t d = 0; d < 20000; ++d) {
    bool above = false;
    for (std::size_t g = 0; g < 3; ++g) {
      const bool out = fresh[d * 3 + g] > thresholds[g];
      each[g] += out ? 1 : 0;
      above = above || out;
    }
    any += above ? 1 : 0;
  }
  // Binomial SD of a 5 % rate over 20000 draws is 0.15 %; the thresholds' own sampling adds as
  // much: 0.6 % is 3 SD of both.
  EXPECT_NEAR(static_cast<double>(any) / 20000, 0.05, 0.006);
  for (std::size_t g = 0; g < 3; ++g) {
    EXPECT_GT(static_cast<double>(each[g]) / 20000, 0.05 / 3 - 0.004) << g;
    EXPECT_LT(static_cast<double>(each[g]) / 20000, 0.05) << g;
  }
}

}  // namespace
}  // namespace gtbake
