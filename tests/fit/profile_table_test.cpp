// The monotone 2D table of docs/profiles.md §8: the isotonic regression against a brute-force
// search over every partition into contiguous blocks, and the table's shape and lookup.
#include "fit/profile_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace gtbake {
namespace {

// The weighted isotonic fit is constant on contiguous blocks at the blocks' weighted means: the
// best of all 2^(n-1) partitions whose block means do not decrease.
double bruteForceIsotonic(const std::vector<double>& y, const std::vector<double>& w) {
  const std::size_t n = y.size();
  double best = INFINITY;
  for (unsigned cuts = 0; cuts < (1u << (n - 1)); ++cuts) {
    double cost = 0.0, previous = -INFINITY;
    bool ok = true;
    std::size_t begin = 0;
    for (std::size_t i = 0; i < n && ok; ++i) {
      if (i + 1 < n && ((cuts >> i) & 1u) == 0) continue;
      double sw = 0.0, swy = 0.0;
      for (std::size_t k = begin; k <= i; ++k) {
        sw += w[k];
        swy += w[k] * y[k];
      }
      const double mean = swy / sw;
      ok = mean >= previous;
      previous = mean;
      for (std::size_t k = begin; k <= i; ++k) cost += w[k] * (y[k] - mean) * (y[k] - mean);
      begin = i + 1;
    }
    if (ok) best = std::min(best, cost);
  }
  return best;
}

TEST(ProfileTable, IsotonicRegressionMatchesBruteForce) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> value(0.0, 1.0), weight(0.5, 3.0);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> y(9), w(9);
    for (std::size_t i = 0; i < y.size(); ++i) {
      y[i] = value(rng) + 0.05 * static_cast<double>(i);
      w[i] = weight(rng);
    }
    const std::vector<double> fit = isotonicRegression(y, w);
    double cost = 0.0;
    for (std::size_t i = 0; i < y.size(); ++i) {
      if (i > 0) {
        EXPECT_GE(fit[i], fit[i - 1]);
      }
      cost += w[i] * (y[i] - fit[i]) * (y[i] - fit[i]);
    }
    EXPECT_NEAR(cost, bruteForceIsotonic(y, w), 1e-12) << trial;
  }
}

TEST(ProfileTable, RowsAreMonotoneWithGOfOneEqualToOne) {
  TableSums sums;
  sums.count.assign(kTableNodes, 2.0);
  sums.count[5] = 0.0;  // an empty node is interpolated
  sums.sum.assign(2, std::vector<double>(kTableNodes, 0.0));
  for (int i = 0; i < kTableNodes; ++i) {
    const double A = static_cast<double>(i) / (kTableNodes - 1);
    sums.sum[0][i] = 2.0 * (1.2 * std::sqrt(A) - 0.1 * std::sin(20.0 * A));  // overshoots, wiggles
    sums.sum[1][i] = 2.0 * A;
  }
  sums.sum[0][5] = 0.0;
  const ProfileTable t = fitProfileTable(sums, {0.2, 0.8});
  for (double rho : {0.1, 0.2, 0.5, 0.8, 0.9}) {
    EXPECT_DOUBLE_EQ(t.lookup(1.0, rho), 1.0);
    double previous = -1.0;
    for (int i = 0; i <= 1000; ++i) {
      const double g = t.lookup(i / 1000.0, rho);
      EXPECT_GE(g, previous);
      EXPECT_LE(g, 1.0);
      previous = g;
    }
  }
  // The exact line's row is reproduced at its nodes; between rows the lookup is linear in rho.
  EXPECT_NEAR(t.lookup(10.0 / 31.0, 0.8), 10.0 / 31.0, 1e-15);
  const double A = 0.37;
  EXPECT_NEAR(t.lookup(A, 0.5), 0.5 * (t.lookup(A, 0.2) + t.lookup(A, 0.8)), 1e-15);
}

}  // namespace
}  // namespace gtbake
