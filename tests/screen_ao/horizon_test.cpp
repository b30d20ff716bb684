// gtao-reference's exact horizon search against dense sampling of the same surface, its direction
// rule and its convergence check (docs/screen_ao.md, "gtao-reference").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "gbuffer_scenes.h"
#include "screen_ao/gtao_reference.h"
#include "screen_ao/horizon_search.h"

namespace gtbake {
namespace {

// The highest sample (texelPlanePoint, within the radius) at `per_pixel` even points per pixel of
// the side's image line up to the image border, texels in the plane of the pixel's own (the same
// normal, the offset within 10⁻⁶) skipped as the search skips them.
double sampledHorizonCos(const GBuffer& g, int i, int j, const Slice& slice, int side,
                         double radius, double floor_cos, int per_pixel) {
  const std::size_t p = static_cast<std::size_t>(j) * g.width + i;
  const Eigen::Vector3d x = viewPosition(g, p);
  const Eigen::Vector3d v = -x.normalized();
  const double sign = side == 0 ? -1.0 : 1.0;
  double best = floor_cos;
  for (int k = 1;; ++k) {
    const double t = static_cast<double>(k) / per_pixel;
    const double sx = i + 0.5 + sign * t * slice.omega.x();
    const double sy = j + 0.5 - sign * t * slice.omega.y();
    if (sx < 0.0 || sy < 0.0 || sx >= g.width || sy >= g.height) break;
    const Texel& texel =
        g.texels[static_cast<std::size_t>(sy) * g.width + static_cast<std::size_t>(sx)];
    const Texel& self = g.texels[p];
    if (texel.normal[0] == self.normal[0] && texel.normal[1] == self.normal[1] &&
        texel.normal[2] == self.normal[2] &&
        std::abs(texel.plane - self.plane) <= 1e-6f * std::abs(self.plane)) {
      continue;
    }
    Eigen::Vector3d sample;
    if (!texelPlanePoint(g, sx, sy, &sample)) continue;
    const Eigen::Vector3d d = sample - x;
    if (d.norm() > radius) continue;
    best = std::max(best, d.dot(v) / d.norm());
  }
  return best;
}

// The search never misses a sample (it is at least the sampled maximum) and dense sampling
// converges to it: the corner's walls rise within 1 cm (texels seen at grazing angles, clamped to
// their slabs), the groove has a crease and two rims.
TEST(ExactHorizon, IsTheLimitOfDenseSampling) {
  for (const Scene& scene : {test::cornerField(0.3), test::grooveField(0.25, 0.25, 2.0)}) {
    const SweepImage image = test::traceImage(scene, 40, 40, 2, 0.5, 1);
    const GBuffer& g = image.gbuffer;
    double worst_gap = 0.0;
    std::size_t raised = 0;
    for (int j = 2; j < g.height; j += 5) {
      for (int i = 3; i < g.width; i += 5) {
        const std::size_t p = static_cast<std::size_t>(j) * g.width + i;
        const Eigen::Vector3d x = viewPosition(g, p);
        const Eigen::Vector3d v = -x.normalized();
        for (int k = 0; k < 8; ++k) {
          const Slice slice = makeViewSlice(g, x, v, viewNormal(g, p), kPi * (k + 0.3) / 8);
          for (int side = 0; side < 2; ++side) {
            const double floor_cos = side == 0 ? slice.sin_n : -slice.sin_n;
            const double exact = exactHorizonCos(g, i, j, x, v, slice, side, 0.5, floor_cos);
            const double dense = sampledHorizonCos(g, i, j, slice, side, 0.5, floor_cos, 4096);
            ASSERT_GE(exact, dense - 1e-9) << scene.name << " " << i << " " << j << " " << k;
            worst_gap = std::max(worst_gap, exact - dense);
            raised += exact > floor_cos + 1e-6 ? 1 : 0;
          }
        }
      }
    }
    std::printf("[ info ] %s: exact - dense(4096/px) <= %.2e, %zu horizons above the floor\n",
                scene.name.c_str(), worst_gap, raised);
    EXPECT_LT(worst_gap, 1e-3) << scene.name;
    EXPECT_GT(raised, 100u) << scene.name;  // the occluders are found
  }
}

// Without refinement the direction rule is the even-slice sum of the memo (Alg. 1 line 30).
TEST(GtaoReference, WithoutRefinementIsTheEvenSliceSum) {
  const SweepImage image = test::traceImage(test::cornerField(0.3), 24, 24, 2, 0.3, 1);
  const GBuffer& g = image.gbuffer;
  GtaoReferenceSettings s;
  s.radius = 0.3;
  s.slices = 12;
  s.refine_levels = 0;
  for (const auto& [i, j] : {std::pair{5, 7}, std::pair{12, 12}, std::pair{19, 3}}) {
    const std::size_t p = static_cast<std::size_t>(j) * g.width + i;
    const Eigen::Vector3d x = viewPosition(g, p);
    const Eigen::Vector3d v = -x.normalized();
    double sum = 0.0;
    for (int k = 0; k < s.slices; ++k) {
      const Slice slice = makeViewSlice(g, x, v, viewNormal(g, p), kPi * (k + 0.5) / s.slices);
      for (int side = 0; side < 2; ++side) {
        const double floor_cos = side == 0 ? slice.sin_n : -slice.sin_n;
        const double c = exactHorizonCos(g, i, j, x, v, slice, side, s.radius, floor_cos);
        sum += slice.projected_length * arcIntegral(horizonAngle(c, side, slice.n), slice.n);
      }
    }
    double a = 0.0;
    Eigen::Vector3d bent;
    gtaoReferencePixel(g, i, j, s, &a, &bent);
    EXPECT_NEAR(a, sum / s.slices, 1e-12) << i << " " << j;
  }
}

// Where horizonUnclamped holds, unclampedHorizon is horizonOf bit for bit, without the slice's
// angle n (docs/screen_ao.md, "gtao-reference"): random slices, N' near ±π/2 from V included, and
// horizons at, just above and far above the hemisphere's end, and above 1.
TEST(GtaoReference, UnclampedHorizonIsHorizonOf) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const auto unit = [&] {
    Eigen::Vector3d u;
    do u = Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
    while (u.squaredNorm() > 1.0 || u.squaredNorm() < 1e-6);
    return Eigen::Vector3d(u.normalized());
  };
  std::size_t unclamped = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    const Eigen::Vector3d v = unit();
    const Eigen::Vector3d w = unit();
    const Eigen::Vector3d o = (w - v * v.dot(w)).normalized();
    Eigen::Vector3d normal = unit();
    if (trial % 4 == 0) {  // N' within 10⁻³ of ±π/2 from V, where the cos n bound decides
      normal = (std::copysign(1.0, uniform(rng)) * o + 2e-3 * uniform(rng) * v).normalized();
    }
    const Slice without = sliceThroughWithoutAngle(v, o, normal, Eigen::Vector2d(1.0, 0.0));
    const Slice slice = withAngle(without);
    for (int side = 0; side < 2; ++side) {
      const double floor_cos = side == 0 ? slice.sin_n : -slice.sin_n;
      const double above = std::pow(10.0, -12.0 * std::abs(uniform(rng)));
      for (const double c : {floor_cos, floor_cos + 1e-9, std::nextafter(floor_cos + 1e-9, 2.0),
                             floor_cos + 2e-9, floor_cos + above, uniform(rng), 1.0 + 1e-12}) {
        if (!horizonUnclamped(c, floor_cos, without)) continue;
        ++unclamped;
        const Angle fast = unclampedHorizon(c, side);
        const Angle plain = horizonOf(c, side, slice);
        EXPECT_EQ(fast.a, plain.a);
        EXPECT_EQ(fast.s, plain.s);
        EXPECT_EQ(fast.c, plain.c);
      }
    }
  }
  EXPECT_GT(unclamped, 500000u);
}

// The convergence check doubles the discretisation, and the defaults pass its bar on the test
// height fields.
TEST(GtaoReference, DoublingMovesLessThanTheBar) {
  const SweepImage corner = test::traceImage(test::cornerField(0.3), 64, 64, 2, 1.0, 1);
  const SweepImage groove = test::traceImage(test::grooveField(0.25, 0.25, 2.0), 64, 64, 2, 1.0, 1);
  const GtaoReferenceSettings defaults;
  const ReferenceConvergence c = referenceConvergence({&corner.gbuffer, &groove.gbuffer}, defaults);
  EXPECT_EQ(c.doubled.slices, 2 * defaults.slices);
  EXPECT_EQ(c.doubled.refine_tolerance, 0.5 * defaults.refine_tolerance);
  EXPECT_EQ(c.doubled.refine_levels, defaults.refine_levels + 1);
  EXPECT_EQ(c.pixels, 128u);
  std::printf("[ info ] doubling moves A by %.5f RMS (max %.4f)\n", c.rms_change, c.max_change);
  EXPECT_LT(c.rms_change, kConvergenceBar);
}

}  // namespace
}  // namespace gtbake
