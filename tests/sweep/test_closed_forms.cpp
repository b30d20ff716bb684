// A, p_k and G against closed forms (SPEC §1.1; docs/sweep.md "Tests"). Each estimate must lie
// within 3 standard errors of its closed form, the standard error taken from the multinomial
// variance p(1 − p)/N of N independent walks (an upper bound: stratifying the first bounce only
// lowers the variance). Where the mesh only approximates the curved surface, the closed form is
// widened by the tessellation's effect, which each test derives exactly from the mesh.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "closed_form_scenes.h"
#include "scene/procedural_scenes.h"
#include "sweep/escape_image.h"
#include "walk_points.h"

namespace gtbake {
namespace {

constexpr double kPi = 3.14159265358979323846;

double binomialSe(double p, double n) {
  return std::sqrt(std::max(p * (1.0 - p), 0.0) / n);
}

TEST(ClosedForm, OpenPlaneIsFullyUnoccluded) {
  const Scene scene = test::openPlane(1.0);
  const EmbreeTracer tracer(scene);
  WalkSettings settings;
  settings.spp = 32;
  const EscapeImage image = traceEscapeImage(tracer, scene.camera, 48, 32, settings, "", false);
  const auto channels = escapeChannels(image);
  std::size_t unmasked = 0;
  for (const ExrChannel& c : channels) {
    for (std::size_t p = 0; p < image.mask.size(); ++p) {
      const bool geometry = image.mask[p] == 1;
      float expected = 0.0f;
      if (geometry && (c.name == "A" || c.name[0] == 'G' || c.name == "mask" || c.name == "H0.A" ||
                       c.name == "H1.A")) {
        expected = 1.0f;  // A = G(ρ) = 1 exactly: nothing above a plane
      }
      ASSERT_EQ(c.pixels[p], expected) << c.name << " pixel " << p;
    }
  }
  for (std::uint8_t m : image.mask) unmasked += m;
  EXPECT_GT(unmasked, 0u);
  EXPECT_LT(unmasked, image.mask.size());  // the camera sees past the plane's edge too
}

TEST(ClosedForm, ClosedBoxSeesNoSky) {
  const Scene scene = makeClosedBoxScene();
  const EmbreeTracer tracer(scene);
  WalkSettings settings;
  settings.spp = 64;
  const EscapeImage image = traceEscapeImage(tracer, scene.camera, 32, 32, settings, "", false);
  for (std::uint8_t m : image.mask) ASSERT_EQ(m, 1);
  for (std::uint32_t c : image.counts) ASSERT_EQ(c, 0u);  // A = G = 0: no walk ever escapes
  // Every walk runs all K + 1 segments: rays = pixels × (1 + spp (K + 1)).
  EXPECT_EQ(image.rays, 32u * 32u * (1u + 64u * 4u));
}

// Every point of a spherical bowl sees the same A = 1 − h/(2R) (its opening is a spherical cap;
// the form factor from a point of a sphere to a cap is the cap's area fraction of the sphere,
// 2πR(2R − h)/(4πR²)), so a walk's escape is a geometric
// trial: p_k = A(1 − A)^k and G_K = A(1 − q^{K+1})/(1 − q), q = ρ(1 − A).
TEST(ClosedForm, SphericalCavity) {
  const double radius = 1.0;
  const double depth = 1.4;  // deeper than a hemisphere: A = 0.3
  const int segments = 128;
  const Scene scene = test::sphericalBowl(radius, depth, 48, segments);
  const std::vector<Eigen::Vector3d> rim = test::bowlRim(radius, depth, segments);
  const Eigen::Vector3d centre(0, radius - depth, 0);
  const EmbreeTracer tracer(scene);

  // Points spread over the mesh; each one's exact A on the (convex) mesh is the form factor of
  // the rim polygon. Their range [a_lo, a_hi] bounds A anywhere a walk can land.
  std::mt19937 gen(7);
  std::uniform_int_distribution<std::size_t> pick(0, scene.triangles.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<SurfaceHit> points;
  double exact_sum = 0.0;
  double a_lo = 1.0;
  double a_hi = 0.0;
  const int kPoints = 4096;
  for (int i = 0; i < kPoints; ++i) {
    const auto& t = scene.triangles[pick(gen)];
    const Eigen::Vector3d a = scene.positions[t[0]].cast<double>();
    const Eigen::Vector3d b = scene.positions[t[1]].cast<double>();
    const Eigen::Vector3d c = scene.positions[t[2]].cast<double>();
    double u = unit(gen);
    double v = unit(gen);
    if (u + v > 1.0) {
      u = 1.0 - u;
      v = 1.0 - v;
    }
    const Eigen::Vector3d x = a + u * (b - a) + v * (c - a);
    Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    if (n.dot(centre - x) < 0.0) n = -n;
    const double exact = test::polygonFormFactor(x, n, rim);
    exact_sum += exact;
    a_lo = std::min(a_lo, exact);
    a_hi = std::max(a_hi, exact);
    points.push_back({x.cast<float>(), n.cast<float>()});
  }
  const double a_smooth = 1.0 - depth / (2.0 * radius);
  // Tessellation (chords sag inside the sphere, most visibly next to the rim, where the opening is
  // seen edge-on) moves the mesh's exact A by up to ~3% of A at single points (measured here
  // over 4096 points: [0.291, 0.309] for 48 × 128 facets) and by < 0.5% on average.
  const double exact_mean = exact_sum / kPoints;
  EXPECT_NEAR(exact_mean, a_smooth, 0.005 * a_smooth);
  EXPECT_NEAR(a_lo, a_smooth, 0.05 * a_smooth);
  EXPECT_NEAR(a_hi, a_smooth, 0.05 * a_smooth);

  WalkSettings settings;
  settings.spp = 128;
  settings.bounces = 3;
  const test::PointEstimate e = test::walkPoints(tracer, points, settings);
  EXPECT_NEAR(e.p[0], exact_mean, 3.0 * binomialSe(exact_mean, e.walks));
  // p_k = (1 − A(x_0)) … A(x_k) lies in [a_lo (1 − a_hi)^k, a_hi (1 − a_lo)^k].
  for (int k = 0; k <= settings.bounces; ++k) {
    const double lo = a_lo * std::pow(1.0 - a_hi, k);
    const double hi = a_hi * std::pow(1.0 - a_lo, k);
    const double se = binomialSe(a_smooth * std::pow(1.0 - a_smooth, k), e.walks);
    EXPECT_GT(e.p[k], lo - 3.0 * se) << "k = " << k;
    EXPECT_LT(e.p[k], hi + 3.0 * se) << "k = " << k;
  }
  for (double rho : {0.5, 0.9}) {
    const double q = rho * (1.0 - a_smooth);
    const double g = a_smooth * (1.0 - std::pow(q, settings.bounces + 1)) / (1.0 - q);
    double g_lo = 0.0;
    double g_hi = 0.0;
    double second_moment = 0.0;  // Σ ρ^{2k} p_k: Var(Ĝ) = (Σ ρ^{2k} p_k − G²)/N
    for (int k = 0; k <= settings.bounces; ++k) {
      g_lo += std::pow(rho, k) * a_lo * std::pow(1.0 - a_hi, k);
      g_hi += std::pow(rho, k) * a_hi * std::pow(1.0 - a_lo, k);
      second_moment += std::pow(rho, 2 * k) * a_smooth * std::pow(1.0 - a_smooth, k);
    }
    const double se = std::sqrt((second_moment - g * g) / e.walks);
    EXPECT_GE(g, g_lo);
    EXPECT_LE(g, g_hi);
    EXPECT_GT(e.g(rho), g_lo - 3.0 * se) << "rho = " << rho;
    EXPECT_LT(e.g(rho), g_hi + 3.0 * se) << "rho = " << rho;
  }
}

// Floor centre of a cylindrical well: the sky is the disk of the opening, A = sin²α, tan α = r/d.
TEST(ClosedForm, CylindricalWellFloorCentre) {
  const double radius = 0.5;
  const double depth = 1.0;
  const int segments = 96;
  const Scene scene = test::cylindricalWell(radius, depth, segments);
  const EmbreeTracer tracer(scene);
  const double alpha = std::atan(radius / depth);
  const double a_smooth = std::sin(alpha) * std::sin(alpha);
  // The mesh's opening is the inscribed 96-gon: its exact form factor is the mesh's A.
  const Eigen::Vector3d floor_centre(0, -depth, 0);
  const double a_mesh = test::polygonFormFactor(floor_centre, Eigen::Vector3d::UnitY(),
                                                test::wellOpening(radius, segments));
  EXPECT_LT(a_mesh, a_smooth);
  EXPECT_NEAR(a_mesh, a_smooth, 0.002 * a_smooth);

  // Points within 1e-4 r of the centre: A varies by O((1e-4)²) there.
  std::vector<SurfaceHit> points;
  for (int i = 0; i < 64; ++i) {
    const double phi = 2.0 * kPi * i / 64;
    const Eigen::Vector3d x(1e-4 * radius * std::cos(phi), -depth, 1e-4 * radius * std::sin(phi));
    points.push_back({x.cast<float>(), Eigen::Vector3f::UnitY()});
  }
  WalkSettings settings;
  settings.spp = 4096;
  settings.bounces = 0;
  const test::PointEstimate e = test::walkPoints(tracer, points, settings);
  const double se = binomialSe(a_smooth, e.walks);
  EXPECT_NEAR(e.p[0], a_mesh, 3.0 * se);
  EXPECT_NEAR(e.p[0], a_smooth, 3.0 * se + (a_smooth - a_mesh));
}

// Point on a plane at distance x from where a sphere of radius R touches it: the sphere covers the
// form factor R²·cosθ/D² = R³/(R² + x²)^{3/2}, so A = 1 − R³/(R² + x²)^{3/2}.
TEST(ClosedForm, PlaneBesideSphere) {
  const double radius = 1.0;
  const Scene scene = makeSphereOnPlaneScene(radius, 128);
  const EmbreeTracer tracer(scene);
  // The UV-sphere mesh lies between the spheres of radius r_in (its inradius) and R about the same
  // centre, so its A lies between the closed forms for those two radii (centre height R).
  const Eigen::Vector3d centre(0, radius, 0);
  const double r_in = test::inradius(scene, centre);
  EXPECT_GT(r_in, 0.999 * radius);
  WalkSettings settings;
  settings.spp = 1024;
  settings.bounces = 0;
  for (double x : {0.5, 1.0, 2.0}) {
    auto occluded = [&](double r) {
      const double d2 = x * x + radius * radius;
      return r * r * radius / (d2 * std::sqrt(d2));
    };
    const double a_smooth = 1.0 - occluded(radius);
    std::vector<SurfaceHit> points;
    for (int i = 0; i < 256; ++i) {
      const double phi = 2.0 * kPi * (i + 0.5) / 256;
      points.push_back({Eigen::Vector3f(static_cast<float>(x * std::cos(phi)), 0.0f,
                                        static_cast<float>(x * std::sin(phi))),
                        Eigen::Vector3f::UnitY()});
    }
    const test::PointEstimate e = test::walkPoints(tracer, points, settings);
    const double se = binomialSe(a_smooth, e.walks);
    EXPECT_GT(e.p[0], a_smooth - 3.0 * se) << "x = " << x;
    EXPECT_LT(e.p[0], 1.0 - occluded(r_in) + 3.0 * se) << "x = " << x;
  }
}

}  // namespace
}  // namespace gtbake
