// Leave-one-scene-out: the re-indexed data set is exact, and leaving out the odd scene recovers
// the law the other scenes were drawn from.
#include "fit/scene_mix.h"

#include "fit/multibounce_fit.h"

#include <gtest/gtest.h>

#include "synthetic_sweep.h"

namespace gtbake::test {
namespace {

// Scenes drawn from `laws`, one scene each, pooled like loadSweep pools a sweep's scenes.
SweepData pooled(const std::vector<std::pair<std::string, MultiBounceCoeffs>>& laws) {
  SweepData data;
  std::uint64_t seed = 11;
  for (const auto& [name, coeffs] : laws) {
    const SweepData one = knownCoefficientSweep(coeffs, 4000, 0.001, 0.001, 0.0, seed++);
    if (data.albedos.empty()) {
      data.spp = one.spp;
      data.bounces = one.bounces;
      data.albedos = one.albedos;
      data.full.G.resize(one.full.G.size());
      for (auto& h : data.half) h.G.resize(one.full.G.size());
    }
    const std::size_t begin = data.full.A.size();
    auto append = [](const PointSet& from, PointSet& to) {
      to.A.insert(to.A.end(), from.A.begin(), from.A.end());
      for (std::size_t j = 0; j < from.G.size(); ++j) {
        to.G[j].insert(to.G[j].end(), from.G[j].begin(), from.G[j].end());
      }
    };
    append(one.full, data.full);
    for (int h = 0; h < 2; ++h) append(one.half[h], data.half[h]);
    data.scenes.push_back({name, begin, data.full.A.size()});
  }
  return data;
}

constexpr MultiBounceCoeffs kOther = {3.0, -0.2, 6.0, -0.5, 3.2, 0.7};

TEST(SceneMix, WithoutSceneReindexesExactly) {
  const SweepData data = pooled({{"p1", kPaperCoeffs}, {"odd", kOther}, {"p2", kPaperCoeffs}});
  const SweepData rest = withoutScene(data, 1);
  ASSERT_EQ(rest.scenes.size(), 2u);
  EXPECT_EQ(rest.scenes[0].name, "p1");
  EXPECT_EQ(rest.scenes[1].name, "p2");
  EXPECT_EQ(rest.scenes[1].begin, 4000u);
  EXPECT_EQ(rest.points(), 8000u);
  // Scene p2's points follow p1's unchanged, in every albedo and both halves.
  EXPECT_EQ(rest.full.A[4000], data.full.A[8000]);
  EXPECT_EQ(rest.full.G[6][7999], data.full.G[6][11999]);
  EXPECT_EQ(rest.half[1].G[3][4123], data.half[1].G[3][8123]);
}

TEST(SceneMix, LeavingOutTheOddSceneRecoversTheOthersLaw) {
  const SweepData data = pooled({{"p1", kPaperCoeffs}, {"odd", kOther}, {"p2", kPaperCoeffs}});
  const MultiBounceCoeffs all = fitMultiBounce(data, false).linear.coeffs;
  const auto rows = leaveOneSceneOut(data, false, all, kPaperCoeffs);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1].left_out, "odd");
  // Without the odd scene only the paper's law is left: its curve comes back.
  EXPECT_LT(rows[1].vs_shipped.value, 2e-3);
  EXPECT_GT(rows[1].vs_refit.value, 0.02);
  // Without one of the two paper scenes the odd law weighs half: the curve stays far from both.
  EXPECT_GT(rows[0].vs_shipped.value, 0.02);
  EXPECT_NEAR(rows[0].vs_shipped.value, rows[2].vs_shipped.value, 2e-3);
}

}  // namespace
}  // namespace gtbake::test
