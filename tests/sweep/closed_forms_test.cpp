// A, p_k and G against closed forms (docs/sweep.md §1; docs/sweep.md "Tests"). Each estimate must
// lie within 3 standard errors of its closed form, the standard error taken from the multinomial
// variance p(1 − p)/N of N independent walks (an upper bound: stratifying the first bounce only
// lowers the variance). Where the mesh only approximates the curved surface, the closed form is
// widened by the tessellation's effect, which each test derives exactly from the mesh.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numeric>
#include <random>

#include <tbb/parallel_for.h>

#include "closed_form_scenes.h"
#include "common/math_constants.h"
#include "gtso/ggx.h"
#include "scene/procedural_scenes.h"
#include "support/test_scenes.h"
#include "sweep/escape_image.h"
#include "sweep/specular_occlusion.h"
#include "walk_points.h"

namespace gtbake {
namespace {

double binomialSe(double p, double n) {
  return std::sqrt(std::max(p * (1.0 - p), 0.0) / n);
}

// Ratio Σ num_i / Σ den_i over replicas and its delta-method standard error.
struct Pooled {
  double estimate = 0.0;
  double se = 0.0;
};

template <class Num, class Den>
Pooled pooledRatio(int replicas, const Num& num, const Den& den) {
  double n = 0.0;
  double d = 0.0;
  for (int i = 0; i < replicas; ++i) {
    n += num(i);
    d += den(i);
  }
  Pooled p;
  p.estimate = n / d;
  double var = 0.0;
  for (int i = 0; i < replicas; ++i) {
    const double e = num(i) - p.estimate * den(i);
    var += e * e;
  }
  p.se = std::sqrt(var) / d;
  return p;
}

// S by quadrature of the GGX lobe of r_p > 0 (gtso::GgxDistribution::f, polar coordinates about
// ω_r) against a visibility of local directions (n = +z, ω_o in the (x, z) plane).
template <class Visible>
double lobeQuadrature(double roughness, const gtso::Vec3& wo_local, const Visible& visible) {
  const gtso::GgxDistribution ggx(roughness * roughness);
  const gtso::Vec3 wr{-wo_local.x, 0.0, wo_local.z};
  const gtso::Vec3 e1{wo_local.z, 0.0, wo_local.x};  // ⟂ ω_r in the plane of incidence
  const gtso::Vec3 e2{0.0, 1.0, 0.0};
  // ψ = π t² concentrates the cells at ω_r, where the narrow lobes live.
  const int nt = 2000;
  const int nphi = 768;
  std::vector<double> lobe(nt, 0.0);
  std::vector<double> lit(nt, 0.0);
  tbb::parallel_for(0, nt, [&](int a) {
    const double t = (a + 0.5) / nt;
    const double psi = kPi * t * t;
    const double dpsi = 2.0 * kPi * t / nt;
    for (int b = 0; b < nphi; ++b) {
      const double phi = 2.0 * kPi * (b + 0.5) / nphi;
      const gtso::Vec3 wi = std::cos(psi) * wr + (std::sin(psi) * std::cos(phi)) * e1 +
                            (std::sin(psi) * std::sin(phi)) * e2;
      if (wi.z <= 0.0) continue;
      const double f = ggx.f(wo_local, wi) * wi.z * std::sin(psi) * dpsi;
      lobe[a] += f;
      if (visible(wi)) lit[a] += f;
    }
  });
  double lobe_sum = 0.0;
  double lit_sum = 0.0;
  for (int a = 0; a < nt; ++a) {
    lobe_sum += lobe[a];
    lit_sum += lit[a];
  }
  return lit_sum / lobe_sum;
}

// Above a plane nothing is occluded: A = G(ρ) = 1 and S = 1 for every roughness exactly (the ratio
// estimator of specular_occlusion.h is Σw/Σw), p_k = 0, the normal is +y; the bent normal is the
// normalised sum of cosine directions, n up to its Monte Carlo scatter.
TEST(ClosedForm, OpenPlaneIsFullyUnoccluded) {
  const Scene scene = test::openPlane(1.0);
  const EmbreeTracer tracer(scene);
  WalkSettings settings;
  settings.spp = 32;
  settings.specular_roughness = {0.0, 0.1, 0.25, 0.4, 0.6, 0.8, 1.0};
  settings.specular_spp = 16;
  const EscapeImage image = traceEscapeImage(tracer, scene.camera, 48, 32, settings, "", false);
  const auto channels = escapeChannels(image);
  std::size_t unmasked = 0;
  auto one = [](const std::string& name) {
    return name == "A" || name[0] == 'G' || name == "mask" || name == "H0.A" || name == "H1.A" ||
           name == "NY" || name[0] == 'S' || name.rfind("H0.S", 0) == 0 ||
           name.rfind("H1.S", 0) == 0;
  };
  Eigen::Vector3d bent_sum = Eigen::Vector3d::Zero();
  for (const ExrChannel& c : channels) {
    if (c.name[0] == 'V' || c.name.rfind("BN", 0) == 0 || c.name == "Z") continue;  // below
    for (std::size_t p = 0; p < image.mask.size(); ++p) {
      const bool geometry = image.mask[p] == 1;
      const float expected = geometry && one(c.name) ? 1.0f : 0.0f;
      ASSERT_EQ(c.pixels[p], expected) << c.name << " pixel " << p;
    }
  }
  for (std::size_t p = 0; p < image.mask.size(); ++p) {
    if (image.mask[p] == 0) continue;
    ++unmasked;
    const Eigen::Vector3f b(image.bent[3 * p], image.bent[3 * p + 1], image.bent[3 * p + 2]);
    ASSERT_NEAR(b.norm(), 1.0f, 1e-6f);
    ASSERT_GT(b.y(), 0.9f) << "pixel " << p;
    bent_sum += b.cast<double>();
    ASSERT_GT(image.view[3 * p + 1], 0.0f);  // the camera is above the plane
    // Z: the hit's distance along the camera's forward axis, = t (d · forward) of its ray.
    const int i = static_cast<int>(p % 48);
    const int j = static_cast<int>(p / 48);
    const Ray ray = cameraRay(scene.camera, i, j, 48, 32);
    const double t = -scene.camera.position.y() / ray.direction.y();  // the plane y = 0
    const double z = t * ray.direction.cast<double>().dot(-scene.camera.basis.col(2));
    ASSERT_NEAR(image.depth[p], z, 1e-5 * z) << "pixel " << p;
  }
  EXPECT_GT(unmasked, 0u);
  EXPECT_LT(unmasked, image.mask.size());  // the camera sees past the plane's edge too
  // Tangential components: per walk E[(ω·t)²] = 1/4 under the cosine density and Σ n·ω ≈ 2N/3,
  // so each pixel's b_t has SD ≤ (√N/2)/(2N/3) = 0.75/√N (stratification lowers it).
  const double se = 0.75 / std::sqrt(settings.spp * static_cast<double>(unmasked));
  EXPECT_NEAR(bent_sum.x() / unmasked, 0.0, 3.0 * se);
  EXPECT_NEAR(bent_sum.z() / unmasked, 0.0, 3.0 * se);
}

// Inside a closed box no walk escapes and no specular sample sees the sky: A = G = S = 0; with no
// escaping first bounce the bent normal is n.
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
  EXPECT_TRUE(image.bent == image.normal);

  settings.specular_roughness = {0.0, 0.1, 0.25, 0.4, 0.6, 0.8, 1.0};
  settings.specular_spp = 32;
  const EscapeImage specular = traceEscapeImage(tracer, scene.camera, 32, 32, settings, "", false);
  for (float s : specular.specular) ASSERT_EQ(s, 0.0f);
  EXPECT_GT(specular.rays, image.rays + 32u * 32u * 7u);  // at least one ray per roughness
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

// Floor centre of the cylindrical well, ω_o at 24° from the normal (the opening's half-angle is
// atan(r/d) = 26.6°, so the lobes straddle its edge): Ŝ of traceSpecular, pooled over 256
// replicas, against S by quadrature of the GGX lobe (gtso::GgxDistribution::f, polar coordinates
// about ω_r) against the exact visibility of the mesh's 96-gon opening. Mirror: S = V(ω_r) = 1.
TEST(ClosedForm, WellFloorSpecularOcclusionMatchesQuadrature) {
  const double radius = 0.5;
  const double depth = 1.0;
  const int segments = 96;
  const Scene scene = test::cylindricalWell(radius, depth, segments);
  const EmbreeTracer tracer(scene);
  const std::vector<Eigen::Vector3d> opening = test::wellOpening(radius, segments);
  const Eigen::Vector3d x(0, -depth, 0);
  // Visible iff the ray from x leaves through the opening, the regular polygon with vertices at
  // angles 2πj/N: at polar angle φ the polygon's edge (midpoint angle φ_m) is at distance
  // r cos(π/N) / cos(φ − φ_m) from the centre.
  auto visible = [&](const Eigen::Vector3d& w) {
    if (w.y() <= 0.0) return false;
    const Eigen::Vector3d hit = x + (depth / w.y()) * w;
    double phi = std::atan2(hit.z(), hit.x());
    if (phi < 0.0) phi += 2.0 * kPi;
    const double edge = std::floor(phi * segments / (2.0 * kPi));
    const double mid = 2.0 * kPi * (edge + 0.5) / segments;
    return std::hypot(hit.x(), hit.z()) * std::cos(phi - mid) <= radius * std::cos(kPi / segments);
  };
  EXPECT_TRUE(visible(opening[3] - x + Eigen::Vector3d(-1e-9, 0, 0)));
  EXPECT_FALSE(visible((opening[3] + opening[4]) * 0.5 - x + Eigen::Vector3d(1e-6, 0, 0)));
  const double theta_o = 24.0 * kPi / 180.0;
  // Local frame of the GGX code: n = +z = world +y, ω_o in the (x, z) plane = world (x, y).
  const gtso::Vec3 wo_local{std::sin(theta_o), 0.0, std::cos(theta_o)};
  const Eigen::Vector3f wo(static_cast<float>(std::sin(theta_o)),
                           static_cast<float>(std::cos(theta_o)), 0.0f);
  auto world = [](const gtso::Vec3& v) { return Eigen::Vector3d(v.x, v.z, -v.y); };
  const std::vector<double> roughness = {0.0, 0.1, 0.25, 0.4, 0.6, 0.8};

  WalkSettings settings;
  settings.specular_roughness = roughness;
  settings.specular_spp = 256;
  const int replicas = 256;
  std::vector<double> sums(replicas * 4 * roughness.size(), 0.0);
  tbb::parallel_for(0, replicas, [&](int i) {
    SpecularScratch scratch;
    const float wo_f[3] = {wo.x(), wo.y(), wo.z()};
    traceSpecular(tracer, SurfaceHit{x.cast<float>(), Eigen::Vector3f::UnitY()}, wo_f, settings,
                  static_cast<std::uint64_t>(i), &sums[i * 4 * roughness.size()], &scratch);
  });

  for (std::size_t j = 0; j < roughness.size(); ++j) {
    const std::size_t stride = 4 * roughness.size();
    const Pooled pooled = pooledRatio(
        replicas, [&](int i) { return sums[i * stride + 4 * j] + sums[i * stride + 4 * j + 2]; },
        [&](int i) { return sums[i * stride + 4 * j + 1] + sums[i * stride + 4 * j + 3]; });
    const double estimate = pooled.estimate;
    const double se = pooled.se;
    // Mirror: ω_r at 24° leaves through the opening.
    const double exact =
        roughness[j] > 0.0
            ? lobeQuadrature(roughness[j], wo_local,
                             [&](const gtso::Vec3& wi) { return visible(world(wi)); })
            : 1.0;
    std::printf("[ info ] r_p %.2f: S = %.5f ± %.5f, quadrature %.5f\n", roughness[j], estimate, se,
                exact);
    if (roughness[j] == 0.0) {
      EXPECT_EQ(estimate, 1.0);
    } else {
      EXPECT_NEAR(estimate, exact, 3.0 * se + 2e-4) << "r_p " << roughness[j];
    }
  }
}

// Point on the plane at distance d = R beside the sphere: b leans away from it. With the
// sphere's cap c (axis from x to the centre, half-angle γ, sin γ = r/D), ∫ V (n·ω) ω dω =
// (2π/3) n − a (c·n) c − β (n − (c·n) c), a = ∫_cap cos²ψ = 2π(1 − cos³γ)/3 and
// β = ∫_cap sin²ψ cos²φ = π(2/3 − cos γ + cos³γ/3), so tan(tilt) = v_x / v_y. The mesh lies
// between the spheres of radius r_in and R (closed forms for both), ± 3 SE of the pooled estimate.
TEST(ClosedForm, BentNormalBesideSphere) {
  const double radius = 1.0;
  const Scene scene = makeSphereOnPlaneScene(radius, 128);
  const EmbreeTracer tracer(scene);
  const Eigen::Vector3d centre(0, radius, 0);
  const double r_in = test::inradius(scene, centre);
  const double d = 1.0;
  auto tilt = [&](double r) {
    const Eigen::Vector3d n = Eigen::Vector3d::UnitY();
    const Eigen::Vector3d c = (centre - Eigen::Vector3d(d, 0, 0)).normalized();
    const double big_d = (centre - Eigen::Vector3d(d, 0, 0)).norm();
    const double cos_g = std::sqrt(1.0 - r * r / (big_d * big_d));
    const double a = 2.0 * kPi * (1.0 - cos_g * cos_g * cos_g) / 3.0;
    const double beta = kPi * (2.0 / 3.0 - cos_g + cos_g * cos_g * cos_g / 3.0);
    const double cn = c.dot(n);
    const Eigen::Vector3d v = (2.0 * kPi / 3.0) * n - a * cn * c - beta * (n - cn * c);
    return std::atan2(v.x(), v.y());
  };
  WalkSettings settings;
  settings.spp = 1024;
  settings.bounces = 0;
  const int replicas = 512;
  std::vector<double> sums(3 * replicas, 0.0);
  tbb::parallel_for(0, replicas, [&](int i) {
    WalkScratch scratch;
    std::uint32_t counts[2] = {0, 0};
    countEscapes(tracer,
                 SurfaceHit{Eigen::Vector3f(static_cast<float>(d), 0, 0), Eigen::Vector3f::UnitY()},
                 settings, static_cast<std::uint64_t>(i), counts, &scratch, &sums[3 * i]);
  });
  double tx = 0.0;
  double ny = 0.0;
  for (int i = 0; i < replicas; ++i) {
    tx += sums[3 * i];
    ny += sums[3 * i + 1];
  }
  const double estimate = std::atan2(tx, ny);
  double var = 0.0;  // delta method for atan(T/N) over independent replicas
  for (int i = 0; i < replicas; ++i) {
    const double e = ny * sums[3 * i] - tx * sums[3 * i + 1];
    var += e * e;
  }
  const double se = std::sqrt(var) / (tx * tx + ny * ny);
  const double lo = std::min(tilt(r_in), tilt(radius));
  const double hi = std::max(tilt(r_in), tilt(radius));
  std::printf("[ info ] bent-normal tilt %.4f° ± %.4f°, closed form [%.4f°, %.4f°]\n",
              estimate * 180 / kPi, se * 180 / kPi, lo * 180 / kPi, hi * 180 / kPi);
  EXPECT_GT(estimate, lo - 3.0 * se);
  EXPECT_LT(estimate, hi + 3.0 * se);
}

// A surface point of the parallel planes: where the vertical ray from (x, h/2, z) hits the floor
// (down) or the ceiling (up), so its offset scale is the tracer's.
SurfaceHit planePoint(const EmbreeTracer& tracer, double h, float x, float z, bool floor) {
  SurfaceHit hit;
  const Ray ray{Eigen::Vector3f(x, static_cast<float>(0.5 * h), z),
                Eigen::Vector3f(0.0f, floor ? -1.0f : 1.0f, 0.0f)};
  EXPECT_TRUE(tracer.intersect(ray, INFINITY, &hit));
  return hit;
}

// Floor and ceiling at height h, two infinite parallel planes (docs/sweep.md "Near-field truth"):
// a cosine-distributed segment from either plane leaves at θ from its normal and hits the other at
// h/cos θ, beyond R iff cos θ < h/R, and cos²θ is uniform under the cosine density, so every
// segment escapes at radius R ≥ h with q = (h/R)², independently of the walk before it:
// p_{k,R} = (1 − q)^k q and G_R(ρ) = q Σ_{k≤K} (ρ(1 − q))^k. The unbounded walks never escape
// (a segment reaching the planes' edge 10 km away has cos θ < 5e-5: probability 2.5e-9). Each
// p̂_{k,R} within 4 binomial SE, each Ĝ_R(ρ) within 4 multinomial SE, for two seeds; both
// traversals give the same counts.
TEST(ClosedForm, NearFieldBetweenParallelPlanes) {
  const double h = 0.5;
  const EmbreeTracer tracer(test::parallelPlanes(h));
  WalkSettings settings;
  settings.spp = 1 << 12;
  settings.bounces = 3;
  settings.gbuffer_radii = {0.6f, 1.0f, 2.5f};
  const std::size_t k1 = settings.bounces + 1;
  const std::size_t radii = settings.gbuffer_radii.size();
  const int points = 64;  // half on the floor, half on the ceiling
  for (std::uint64_t seed : {1u, 2u}) {
    settings.seed = seed;
    std::vector<std::uint32_t> counts(points * 2 * k1, 0);
    std::vector<std::uint32_t> near(points * radii * 2 * k1, 0);
    std::vector<std::uint32_t> near_single(near.size(), 0);
    tbb::parallel_for(0, points, [&](int i) {
      const SurfaceHit start =
          planePoint(tracer, h, 0.37f * (i % 8) + 0.1f, 0.29f * (i / 8) + 0.1f, i % 2 == 0);
      WalkScratch scratch;
      countEscapes(tracer, start, settings, i, &counts[i * 2 * k1], &scratch, nullptr,
                   &near[i * radii * 2 * k1]);
      WalkSettings single = settings;
      single.streams = false;
      std::vector<std::uint32_t> unused(2 * k1, 0);
      countEscapes(tracer, start, single, i, unused.data(), &scratch, nullptr,
                   &near_single[i * radii * 2 * k1]);
    });
    EXPECT_EQ(std::accumulate(counts.begin(), counts.end(), 0u), 0u);
    EXPECT_EQ(near, near_single);
    const double n = static_cast<double>(points) * settings.spp;
    for (std::size_t r = 0; r < radii; ++r) {
      const double q = std::pow(h / settings.gbuffer_radii[r], 2.0);
      std::vector<double> p(k1, 0.0);
      std::vector<double> expected(k1, 0.0);
      for (std::size_t k = 0; k < k1; ++k) {
        for (int i = 0; i < points; ++i) {
          for (std::size_t half = 0; half < 2; ++half)
            p[k] += near[((i * radii + r) * 2 + half) * k1 + k];
        }
        p[k] /= n;
        expected[k] = std::pow(1.0 - q, static_cast<double>(k)) * q;
        EXPECT_NEAR(p[k], expected[k], 4.0 * binomialSe(expected[k], n))
            << "R " << settings.gbuffer_radii[r] << " k " << k << " seed " << seed;
      }
      for (double rho : kSweepAlbedos) {
        double g = 0.0;
        double g_exact = 0.0;
        double second = 0.0;  // Σ ρ^{2k} p_k
        for (std::size_t k = k1; k-- > 0;) {
          g = g * rho + p[k];
          g_exact = g_exact * rho + expected[k];
          second = second * rho * rho + expected[k];
        }
        EXPECT_NEAR(g, g_exact, 4.0 * std::sqrt((second - g_exact * g_exact) / n))
            << "R " << settings.gbuffer_radii[r] << " rho " << rho << " seed " << seed;
      }
    }
  }
}

// The floor under the ceiling at h, ω_o at 40° from the normal: a ray leaving at θ_i hits the
// ceiling at h/cos θ_i, so V_R(ω_i) = [cos θ_i < h/R] and the unbounded S is 0. Mirror:
// S_R = [h/cos θ_r > R], here h/cos 40° = 0.653 m: S_R = 1 at R = 0.6 and 0 at R = 1 and 2.5
// exactly. Rough lobes: Ŝ_R pooled over 128 replicas against the quadrature of the lobe with that
// visibility, within 3 SE.
TEST(ClosedForm, NearFieldSpecularUnderCeiling) {
  const double h = 0.5;
  const EmbreeTracer tracer(test::parallelPlanes(h));
  const double theta_o = 40.0 * kPi / 180.0;
  const gtso::Vec3 wo_local{std::sin(theta_o), 0.0, std::cos(theta_o)};
  const float wo[3] = {static_cast<float>(std::sin(theta_o)), static_cast<float>(std::cos(theta_o)),
                       0.0f};
  const std::vector<double> roughness = {0.0, 0.25, 0.5};
  WalkSettings settings;
  settings.specular_roughness = roughness;
  settings.specular_spp = 256;
  settings.gbuffer_radii = {0.6f, 1.0f, 2.5f};
  const std::size_t J = roughness.size();
  const std::size_t radii = settings.gbuffer_radii.size();
  const int replicas = 128;
  std::vector<double> sums(replicas * 4 * J, 0.0);
  std::vector<double> near(replicas * 2 * radii * J, 0.0);
  const SurfaceHit start = planePoint(tracer, h, 0.1f, 0.1f, true);
  tbb::parallel_for(0, replicas, [&](int i) {
    SpecularScratch scratch;
    traceSpecular(tracer, start, wo, settings, static_cast<std::uint64_t>(i), &sums[i * 4 * J],
                  &scratch, &near[i * 2 * radii * J]);
  });
  for (std::size_t j = 0; j < J; ++j) {
    const auto den = [&](int i) {
      return sums[i * 4 * J + 4 * j + 1] + sums[i * 4 * J + 4 * j + 3];
    };
    const Pooled unbounded = pooledRatio(
        replicas, [&](int i) { return sums[i * 4 * J + 4 * j] + sums[i * 4 * J + 4 * j + 2]; },
        den);
    EXPECT_LT(unbounded.estimate, 1e-6) << "r_p " << roughness[j];
    for (std::size_t r = 0; r < radii; ++r) {
      const double radius = settings.gbuffer_radii[r];
      const std::size_t at = 2 * (r * J + j);
      const Pooled s_r = pooledRatio(
          replicas,
          [&](int i) { return near[i * 2 * radii * J + at] + near[i * 2 * radii * J + at + 1]; },
          den);
      if (roughness[j] == 0.0) {
        EXPECT_EQ(s_r.estimate, h / std::cos(theta_o) > radius ? 1.0 : 0.0) << "R " << radius;
        continue;
      }
      const double exact = lobeQuadrature(roughness[j], wo_local,
                                          [&](const gtso::Vec3& wi) { return wi.z < h / radius; });
      std::printf("[ info ] r_p %.2f R %.2f: S_R = %.5f ± %.5f, quadrature %.5f\n", roughness[j],
                  radius, s_r.estimate, s_r.se, exact);
      EXPECT_NEAR(s_r.estimate, exact, 3.0 * s_r.se + 2e-4)
          << "r_p " << roughness[j] << " R " << radius;
    }
  }
}

}  // namespace
}  // namespace gtbake
