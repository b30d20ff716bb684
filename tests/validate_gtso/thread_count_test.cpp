// validate-gtso's scene-level statistics and u fits give the same bits on 1 and 2 threads
// (docs/validate_gtso.md §5): every parallel loop writes disjoint outputs and reduces in a fixed
// order, whatever the schedule. 24 scenes, so the sign-flip tests draw their random patterns
// (more than kExactSignFlipScenes).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "common/math_constants.h"
#include "common/threads.h"
#include "validate_gtso/cone_u_fit.h"
#include "validate_gtso/scene_paired_test.h"
#include "validate_gtso/so_floor.h"
#include "validate_gtso/u_scene_interval.h"

namespace gtbake {
namespace {

constexpr int kScenes = 24;
constexpr float kRoughness[] = {0.1f, 0.25f, 0.4f, 0.6f, 0.8f};

std::vector<SpecularSample> coneTruths() {
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::vector<SpecularSample> samples;
  for (int scene = 0; scene < kScenes; ++scene) {
    const double u = std::pow(10.0, -0.5 - 1.5 * unit(gen));
    for (int p = 0; p < 400; ++p) {
      const double A = unit(gen), beta = 0.5 * kPi * unit(gen);
      for (int j = 0; j < 5; ++j) {
        SpecularSample s;
        s.scene = scene;
        s.roughness = j;
        s.r_p = kRoughness[j];
        s.A = static_cast<float>(A);
        setConeAngles(&s, beta);
        s.n_dot_v = static_cast<float>(unit(gen));
        s.n_dot_b = static_cast<float>(unit(gen));
        s.truth = coneAt(s, u, true) + noise(gen);
        samples.push_back(s);
      }
    }
  }
  return samples;
}

// Every number the statistics produce, in a fixed order.
std::vector<double> statistics(const std::vector<SpecularSample>& samples, int threads) {
  const ThreadLimit limit(threads);
  std::vector<int> cluster_of;
  for (int s = 0; s < kScenes; ++s) cluster_of.push_back(s);
  std::vector<double> out;
  for (bool perceptual : {false, true}) {
    const UFits f = fitConeU(samples, perceptual);
    for (const UFit& x : {f.all, f.rp_ge_0_3}) {
      out.insert(out.end(), {x.u, x.low, x.high, x.rmse, x.rmse_paper, x.rmse_uludag});
    }
  }
  const ConeSseTable table = coneSseTable(samples, cluster_of, kScenes, 5);
  for (const auto& law : table.sse)
    for (const auto& cluster : law)
      for (const auto& row : cluster) out.insert(out.end(), row.begin(), row.end());
  const UAnalysis a = analyzeU(table);
  for (int law = 0; law < 2; ++law) {
    out.insert(out.end(), a.interval[law].replicates.begin(), a.interval[law].replicates.end());
    out.insert(out.end(), a.law.held_out_rmse[law].begin(), a.law.held_out_rmse[law].end());
  }
  out.push_back(a.law.test.p_value);
  const SoFloor floor = soFloor(samples, cluster_of, kScenes, 5);
  out.insert(out.end(), floor.rmse.begin(), floor.rmse.end());
  return out;
}

TEST(ValidateGtsoThreads, SameBitsOnOneAndTwoThreads) {
  const std::vector<SpecularSample> samples = coneTruths();
  const std::vector<double> one = statistics(samples, 1);
  const std::vector<double> two = statistics(samples, 2);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(double)), 0);
}

}  // namespace
}  // namespace gtbake
