// gtao-reference against ray-traced truth where the depth buffer holds every occluder, and the
// sweep's A_R against its closed form (docs/screen_ao.md, "Tests").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "gbuffer_scenes.h"
#include "scene/mesh_builder.h"
#include "scene/procedural_scenes.h"
#include "screen_ao/gtao_reference.h"
#include "screen_ao/screen_ao_stats.h"
#include "sweep/escape_image.h"

namespace gtbake {
namespace {

// Â of gtao-reference against the mean of two independent traces of A_R (seeds 1, 2) on the
// pixels whose radius disc lies inside the image; the Monte Carlo variance of that mean, estimated
// from the two traces' difference, is subtracted from the mean squared error.
struct Agreement {
  double rms = 0.0;  // Monte Carlo noise included
  double excess_rms = 0.0;
  double noise_rms = 0.0;
  double bent_mean_deg = 0.0;
  std::size_t pixels = 0;
};

Agreement compareToTraced(const Scene& scene, double radius, int size) {
  const SweepImage one = test::traceImage(scene, size, size, 1024, radius, 1);
  const SweepImage two = test::traceImage(scene, size, size, 1024, radius, 2);
  const GBuffer& g = one.gbuffer;
  GtaoReferenceSettings settings;
  settings.radius = radius;
  const AoEstimate e = gtaoReference(g, settings);
  const std::string channel = gbufferRadiusChannelName(radius);
  const std::vector<float>& a1 = one.truth.a_at_radius.at(channel);
  const std::vector<float>& a2 = two.truth.a_at_radius.at(channel);
  Agreement r;
  double squared = 0.0;
  double noise = 0.0;
  double angle = 0.0;
  for (int j = 0; j < g.height; ++j) {
    for (int i = 0; i < g.width; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * g.width + i;
      const double margin = radius * g.pixelsPerMetre(g.depth[p]) + 1.0;
      if (g.mask[p] == 0 || i < margin || j < margin || g.width - i < margin ||
          g.height - j < margin) {
        continue;
      }
      const double truth = 0.5 * (a1[p] + a2[p]);
      squared += (e.a[p] - truth) * (e.a[p] - truth);
      noise += 0.25 * (a1[p] - a2[p]) * (a1[p] - a2[p]);
      // The sweep's bent normal (unbounded walks), the two traces averaged.
      float b[3];
      double length = 0.0;
      for (int c = 0; c < 3; ++c) {
        b[c] = one.truth.bent[3 * p + c] + two.truth.bent[3 * p + c];
        length += b[c] * b[c];
      }
      for (float& c : b) c = static_cast<float>(c / std::sqrt(length));
      angle += angleDegrees(&e.bent[3 * p], b);
      ++r.pixels;
    }
  }
  r.rms = std::sqrt(squared / r.pixels);
  r.excess_rms = std::sqrt(std::max(0.0, (squared - noise) / r.pixels));
  r.noise_rms = std::sqrt(noise / r.pixels);
  r.bent_mean_deg = angle / r.pixels;
  std::printf(
      "[ info ] %s: %zu pixels, RMS %.4f, excess RMS %.4f (noise RMS %.4f), bent %.2f deg\n",
      scene.name.c_str(), r.pixels, r.rms, r.excess_rms, r.noise_rms, r.bent_mean_deg);
  return r;
}

TEST(GtaoReference, MatchesRayTracedGroove) {
  const Agreement r = compareToTraced(test::grooveField(0.25, 0.25, 4.0), 0.6, 64);
  ASSERT_GT(r.pixels, 300u);
  EXPECT_LT(r.rms, 0.01);  // the noisy truth too, not only after its variance is taken out
  EXPECT_LT(r.excess_rms, 0.01);
  EXPECT_LT(r.bent_mean_deg, 2.0);
}

TEST(GtaoReference, MatchesRayTracedCornerFloor) {
  const Agreement r = compareToTraced(test::cornerField(0.1), 0.3, 64);
  ASSERT_GT(r.pixels, 300u);
  EXPECT_LT(r.rms, 0.01);  // the noisy truth too, not only after its variance is taken out
  EXPECT_LT(r.excess_rms, 0.01);
  EXPECT_LT(r.bent_mean_deg, 2.0);
}

// A floor under an infinite ceiling at height h: a walk leaving at angle θ from the normal hits the
// ceiling at h/cos θ, and cos²θ is uniform under the cosine density, so A_R = (h/R)² for R ≥ h
// and 1 for R < h (no hit is that close), while A = 0.
TEST(GbufferRadius, FloorUnderCeilingClosedForm) {
  const double h = 0.5;
  MeshBuilder mesh;
  const std::vector<double> axis = gradedAxis(1.0, 1.0, kGroundExtent);
  addHeightfield(mesh, axis, axis, [](double, double) { return 0.0; });
  addHeightfield(mesh, axis, axis, [&](double, double) { return h; });
  const Scene scene = mesh.finish("ceiling", lookAt({0, 0.25, 0}, {0, 0, -1}, {0, 1, 0}, 0.8));
  const EmbreeTracer tracer(scene);
  WalkSettings settings;
  settings.spp = 1 << 16;
  settings.bounces = 1;
  settings.gbuffer_radii = {0.25f, 0.75f, 1.0f, 2.0f};
  SurfaceHit start;
  start.position = Eigen::Vector3f(0.1f, 0.0f, 0.2f);
  start.normal = Eigen::Vector3f::UnitY();
  std::vector<std::uint32_t> counts(4, 0);
  // Near-field counts: radius r, half h, bounce k at (2r + h)(K + 1) + k; A_R = c_{0,R}/N.
  std::vector<std::uint32_t> near(settings.gbuffer_radii.size() * counts.size(), 0);
  WalkScratch scratch;
  countEscapes(tracer, start, settings, 7, counts.data(), &scratch, nullptr, near.data());
  EXPECT_EQ(counts[0] + counts[2], 0u);  // A = 0
  for (std::size_t r = 0; r < settings.gbuffer_radii.size(); ++r) {
    const double radius = settings.gbuffer_radii[r];
    const double expected = radius < h ? 1.0 : (h / radius) * (h / radius);
    const double se = std::sqrt(expected * (1.0 - expected) / settings.spp);
    const double a_r = static_cast<double>(near[4 * r] + near[4 * r + 2]) / settings.spp;
    EXPECT_NEAR(a_r, expected, 4.0 * se + 1e-9) << "R = " << radius;
  }
}

}  // namespace
}  // namespace gtbake
