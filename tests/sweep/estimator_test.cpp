// Properties of the walk estimator itself: the cosine sampler's moments, the variance reduction of
// the stratified first bounce (without bias), and the sky radius R.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "closed_form_scenes.h"
#include "common/rng.h"
#include "gtso/ggx.h"
#include "sweep/escape_image.h"
#include "sweep/philox_lanes.h"
#include "sweep/specular_occlusion.h"
#include "walk_points.h"

namespace gtbake {
namespace {

// Under pdf cosθ/π: E[cosθ] = 2/3 and E[cos²θ] = 1/2, every direction in the upper hemisphere.
TEST(Estimator, CosineDirectionMoments) {
  const Eigen::Vector3f n = Eigen::Vector3f(0.3f, -0.5f, 0.8f).normalized();
  const CounterRng rng(3, 0);
  const int count = 1 << 18;
  double m1 = 0.0;
  double m2 = 0.0;
  for (int i = 0; i < count; ++i) {
    const auto u = rng.uniform4(static_cast<std::uint64_t>(i), 0);
    const Eigen::Vector3f d = cosineDirection(n, u[0], u[1]);
    ASSERT_NEAR(d.norm(), 1.0f, 1e-5f);
    ASSERT_GE(d.dot(n), -1e-6f);
    m1 += d.dot(n);
    m2 += d.dot(n) * d.dot(n);
  }
  m1 /= count;
  m2 /= count;
  // Var(cosθ) = 1/2 − 4/9 = 1/18; Var(cos²θ) = E[cos⁴θ] − 1/4 = 1/3 − 1/4 = 1/12.
  EXPECT_NEAR(m1, 2.0 / 3.0, 3.0 * std::sqrt(1.0 / 18.0 / count));
  EXPECT_NEAR(m2, 0.5, 3.0 * std::sqrt(1.0 / 12.0 / count));
}

// 512 independent replicas of a 64-walk estimate of A at the floor centre of a well: stratifying
// the first bounce keeps the mean (unbiased) and cuts the variance well below the binomial
// A(1 − A)/64 that independent walks give.
TEST(Estimator, StratifiedFirstBounceReducesVarianceWithoutBias) {
  const Scene scene = test::cylindricalWell(0.5, 1.0, 96);
  const EmbreeTracer tracer(scene);
  const double a_mesh =
      test::polygonFormFactor({0, -1, 0}, Eigen::Vector3d::UnitY(), test::wellOpening(0.5, 96));
  const std::vector<SurfaceHit> points(512, SurfaceHit{{0, -1, 0}, {0, 1, 0}});
  double variance[2];
  for (int stratify = 0; stratify < 2; ++stratify) {
    WalkSettings settings;
    settings.spp = 64;
    settings.bounces = 0;
    settings.seed = 11;
    settings.stratify_first_bounce = stratify == 1;
    const std::size_t per_point = 2;
    std::vector<std::uint32_t> counts(points.size() * per_point, 0);
    tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) {
      WalkScratch scratch;
      countEscapes(tracer, points[i], settings, i, &counts[i * per_point], &scratch);
    });
    double sum = 0.0;
    double sum2 = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double a = (counts[2 * i] + counts[2 * i + 1]) / 64.0;
      sum += a;
      sum2 += a * a;
    }
    const double n = static_cast<double>(points.size());
    const double mean = sum / n;
    variance[stratify] = (sum2 - n * mean * mean) / (n - 1.0);
    const double binomial = a_mesh * (1.0 - a_mesh) / 64.0;
    EXPECT_NEAR(mean, a_mesh, 3.0 * std::sqrt(binomial / n)) << "stratified " << stratify;
  }
  const double binomial = a_mesh * (1.0 - a_mesh) / 64.0;
  // A sample variance of 512 replicas is within ±~19% (3σ) of the true one.
  EXPECT_NEAR(variance[0], binomial, 0.2 * binomial);
  EXPECT_LT(variance[1], 0.5 * variance[0]);
  std::printf("[ info ] Var(A) over replicas: independent %.3g, stratified %.3g (ratio %.3f)\n",
              variance[0], variance[1], variance[1] / variance[0]);
}

// Nothing lies within R = 0.45 m of the floor centre of a 0.5 m well above the floor, so with that
// sky radius every walk escapes at once: A = G = 1.
TEST(Estimator, SkyRadiusBoundsTheOccluders) {
  const Scene scene = test::cylindricalWell(0.5, 1.0, 96);
  const EmbreeTracer tracer(scene);
  const std::vector<SurfaceHit> points(16, SurfaceHit{{0, -1, 0}, {0, 1, 0}});
  WalkSettings settings;
  settings.spp = 256;
  settings.radius = 0.45f;
  const test::PointEstimate near = test::walkPoints(tracer, points, settings);
  EXPECT_EQ(near.p[0], 1.0);
  settings.radius = INFINITY;
  const test::PointEstimate far = test::walkPoints(tracer, points, settings);
  EXPECT_LT(far.p[0], 0.5);
}

}  // namespace
}  // namespace gtbake

namespace gtbake {
namespace {

// The stream traversal (all walks of a pixel bounce by bounce, array Philox, batched kernels)
// against an independent reference written here from the definitions: Random123 through
// CounterRng (not PhiloxLanes), the first-bounce stratum computed from the grid rule of
// escape_walk.h by hand, one walk at a time through intersect/occluded. Identical counts and
// identical bent-normal sums at every pixel, both traversals of the library included.
TEST(Estimator, StreamAndSingleRayTraversalsAgreeExactly) {
  const Scene scene = test::sphericalBowl(1.0, 1.4, 24, 64);
  const EmbreeTracer tracer(scene);
  WalkSettings settings;
  settings.spp = 24;  // half 12: a 3 × 4 grid
  settings.bounces = 3;
  settings.seed = 9;
  const int res = 12;
  int checked = 0;
  for (int j = 0; j < res; ++j) {
    for (int i = 0; i < res; ++i) {
      SurfaceHit start;
      if (!tracer.intersect(cameraRay(scene.camera, i, j, res, res), INFINITY, &start)) continue;
      const std::uint64_t stream = pixelStream(viewStreamKey("bowl"), j * res + i);
      std::vector<std::uint32_t> counts(2 * (settings.bounces + 1), 0);
      double bent[3] = {0, 0, 0};
      // The transfer sums (docs/sweep.md, "Transfer"): the same bits from both traversals.
      std::vector<double> transfer(9 * (settings.bounces + 1), 0.0);
      WalkScratch scratch;
      countEscapes(tracer, start, settings, stream, counts.data(), &scratch, bent, nullptr,
                   transfer.data());
      WalkSettings single = settings;
      single.streams = false;
      std::vector<std::uint32_t> counts1(counts.size(), 0);
      double bent1[3] = {0, 0, 0};
      std::vector<double> transfer1(transfer.size(), 0.0);
      countEscapes(tracer, start, single, stream, counts1.data(), &scratch, bent1, nullptr,
                   transfer1.data());
      ASSERT_EQ(transfer, transfer1) << "pixel " << i << ", " << j;

      const CounterRng rng(settings.seed, stream);
      std::vector<std::uint32_t> reference(counts.size(), 0);
      double bent_ref[3] = {0, 0, 0};
      for (int s = 0; s < settings.spp; ++s) {
        SurfaceHit at = start;
        std::array<float, 4> u{};
        for (int k = 0; k <= settings.bounces; ++k) {
          if (k % 2 == 0) u = rng.uniform4(static_cast<std::uint64_t>(s), k / 2);
          float u0 = u[2 * (k % 2)];
          float u1 = u[2 * (k % 2) + 1];
          if (k == 0) {  // cell t = s/2 of the 3 × 4 grid of this half
            u0 = (static_cast<float>((s / 2) % 3) + u0) / 3.0f;
            u1 = (static_cast<float>((s / 2) / 3) + u1) / 4.0f;
          }
          const Ray ray{tracer.offsetOrigin(at), cosineDirection(at.normal, u0, u1)};
          const bool escaped = k == settings.bounces ? !tracer.occluded(ray, settings.radius)
                                                     : !tracer.intersect(ray, settings.radius, &at);
          if (escaped) {
            ++reference[(s % 2) * (settings.bounces + 1) + k];
            if (k == 0) {
              for (int c = 0; c < 3; ++c) bent_ref[c] += ray.direction[c];
            }
            break;
          }
        }
      }
      ASSERT_EQ(counts, reference) << "pixel " << i << ", " << j;
      ASSERT_EQ(counts1, reference) << "pixel " << i << ", " << j;
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(bent[c], bent_ref[c]);
        ASSERT_EQ(bent1[c], bent_ref[c]);
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 60);
}

// The vectorized walk loops (array Philox, batched hit frames and directions, AVX2 clones where the
// CPU has them) trace exactly the rays of a scalar replay built from the public one-ray pieces
// (WalkSampler::direction, offsetOrigin, intersect, occluded): identical counts at every pixel.
TEST(Estimator, VectorizedWalksMatchScalarReplay) {
  const Scene scene = test::sphericalBowl(1.0, 1.4, 24, 64);
  const EmbreeTracer tracer(scene);
  WalkSettings settings;
  settings.spp = 48;
  settings.bounces = 4;
  settings.seed = 5;
  const int res = 16;
  int checked = 0;
  for (int j = 0; j < res; ++j) {
    for (int i = 0; i < res; ++i) {
      SurfaceHit start;
      if (!tracer.intersect(cameraRay(scene.camera, i, j, res, res), INFINITY, &start)) continue;
      const std::uint64_t stream = static_cast<std::uint64_t>(j) * res + i;
      std::vector<std::uint32_t> counts(2 * (settings.bounces + 1), 0);
      WalkScratch scratch;
      countEscapes(tracer, start, settings, stream, counts.data(), &scratch);
      const WalkSampler sampler(settings, stream);
      std::vector<std::uint32_t> replay(counts.size(), 0);
      for (int s = 0; s < settings.spp; ++s) {
        SurfaceHit at = start;
        for (int k = 0; k <= settings.bounces; ++k) {
          const Ray ray{tracer.offsetOrigin(at), sampler.direction(at.normal, s, k)};
          const bool escaped = k == settings.bounces ? !tracer.occluded(ray, settings.radius)
                                                     : !tracer.intersect(ray, settings.radius, &at);
          if (escaped) {
            ++replay[(s & 1) * (settings.bounces + 1) + k];
            break;
          }
        }
      }
      ASSERT_EQ(counts, replay) << "pixel " << i << ", " << j;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

// The walks' array Philox (written out round by round for vectorization) gives exactly Random123's
// Philox4x32-10 words through CounterRng, for seeds and streams using all 64 bits.
TEST(Estimator, PhiloxLanesMatchCounterRng) {
  const std::uint64_t keys[][2] = {
      {1, 0}, {7, 36863}, {0x123456789abcdefull, 0xfedcba9876543210ull}};
  std::vector<std::int32_t> index(1003);  // not a multiple of 8: the AVX2 path and its tail
  for (int i = 0; i < 1003; ++i) index[i] = i * 1049 % 1048576;
  std::vector<std::uint32_t> w[4];
  for (auto& v : w) v.resize(index.size());
  for (const auto& key : keys) {
    const CounterRng rng(key[0], key[1]);
    const PhiloxLanes lanes(key[0], key[1]);
    for (std::uint32_t block : {0u, 1u, 5u}) {
      lanes.words(index.data(), static_cast<int>(index.size()), block, w[0].data(), w[1].data(),
                  w[2].data(), w[3].data());
      for (std::size_t i = 0; i < index.size(); ++i) {
        const auto expected = rng.words(static_cast<std::uint64_t>(index[i]), block);
        for (int c = 0; c < 4; ++c) ASSERT_EQ(w[c][i], expected[c]) << i << " " << block;
        for (int c = 0; c < 4; ++c) {
          ASSERT_EQ(wordToUniform(w[c][i]), rng.uniform4(index[i], block)[c]);
        }
      }
    }
  }
}

// The specular samples' float VNDF kernel against gtso::GgxDistribution (double): the same ω_i
// and weight G2/G1 for every u of a grid, roughness from near-mirror to rough, views from normal
// to grazing (float rounding, amplified ~1/α near the mirror direction by the unstretch).
TEST(Estimator, FloatVndfMatchesGgxSampler) {
  const double kPiHere = 3.14159265358979323846;
  for (double r : {0.05, 0.1, 0.25, 0.4, 0.6, 0.8, 1.0}) {
    const double alpha = r * r;
    const gtso::GgxDistribution ggx(alpha);
    for (double theta_deg : {0.0, 10.0, 45.0, 75.0, 89.0}) {
      const double th = theta_deg * kPiHere / 180.0;
      // Off the x axis, so the stretched frame's T1 is not axis-aligned.
      const gtso::Vec3 wo{std::sin(th) * 0.6, std::sin(th) * 0.8, std::cos(th)};
      const float wo_f[3] = {static_cast<float>(wo.x), static_cast<float>(wo.y),
                             static_cast<float>(wo.z)};
      const VndfFrame frame = makeVndfFrame(alpha, wo_f);
      for (int a = 0; a < 64; ++a) {
        for (int b = 0; b < 64; ++b) {
          const gtso::Point2 u{(a + 0.37) / 64.0, (b + 0.61) / 64.0};
          float wi[3];
          float weight;
          vndfReflect(frame, static_cast<float>(u.x), static_cast<float>(u.y), wi, &weight);
          const gtso::Vec3 ref = ggx.sampleWi(wo, u);
          const double tol = 2e-5 / std::max(alpha, 0.01) + 1e-5;
          ASSERT_NEAR(wi[0], ref.x, tol) << r << " " << theta_deg << " " << a << " " << b;
          ASSERT_NEAR(wi[1], ref.y, tol) << r << " " << theta_deg << " " << a << " " << b;
          ASSERT_NEAR(wi[2], ref.z, tol) << r << " " << theta_deg << " " << a << " " << b;
          if (std::abs(ref.z) > 1e-3) {
            ASSERT_NEAR(weight, ggx.weight(wo, ref), 1e-4) << r << " " << theta_deg;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace gtbake
