// The sanity anchor of docs/lighting.md §4: a floor point beside an infinite wall. The wall
// hides exactly the half of the floor's hemisphere that points at it, so A = 1/2 at every
// distance. G(ρ, L) from the sweep's walks and transfer (countEscapes on Embree) is checked
// against a brute-force Monte Carlo integral that shares nothing with the sweep: its own random
// numbers, cosine sampler and ray-plane intersections, L evaluated from the same SH coefficients.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "common/math_constants.h"
#include "common/spherical_harmonics.h"
#include "fit/multibounce_coeffs.h"
#include "lighting/environment.h"
#include "scene/scene.h"
#include "sweep/embree_tracer.h"
#include "sweep/escape_walk.h"

namespace gtbake {
namespace {

constexpr double kExtent = 8192.0;  // the planes' half size (metres): "infinite" to ~1e-4 of A
constexpr int kBounces = 3;
constexpr double kDistance = 0.5;  // the point's distance from the wall

// Graded cell edges 0, 1/8, 1/4, …, kExtent (so triangles near the point are small and the ray
// offsets those of a small scene, docs/sweep.md §3), mirrored when `symmetric`.
std::vector<float> gradedEdges(bool symmetric) {
  std::vector<float> up = {0.0f};
  for (double e = 0.125; e <= kExtent; e *= 2.0) up.push_back(static_cast<float>(e));
  if (!symmetric) return up;
  std::vector<float> out;
  for (std::size_t i = up.size(); i-- > 1;) out.push_back(-up[i]);
  out.insert(out.end(), up.begin(), up.end());
  return out;
}

// The floor y = 0 (x ≥ 0) and the wall x = 0 (y ≥ 0), both out to kExtent in z.
Scene floorAndWall() {
  Scene scene;
  scene.name = "wall";
  const std::vector<float> u = gradedEdges(false);
  const std::vector<float> z = gradedEdges(true);
  for (int plane = 0; plane < 2; ++plane) {
    for (std::size_t i = 0; i + 1 < u.size(); ++i) {
      for (std::size_t j = 0; j + 1 < z.size(); ++j) {
        const auto base = static_cast<std::uint32_t>(scene.positions.size());
        for (int c = 0; c < 4; ++c) {
          const float a = u[i + (c & 1)];
          const float b = z[j + (c >> 1)];
          scene.positions.push_back(plane == 0 ? Eigen::Vector3f(a, 0, b)
                                               : Eigen::Vector3f(0, a, b));
        }
        scene.triangles.push_back({base, base + 1, base + 3});
        scene.triangles.push_back({base, base + 3, base + 2});
      }
    }
  }
  return scene;
}

// Per-walk contributions ρ^k L(ω_k) of an independent path tracer over the same two planes.
struct BruteForce {
  std::vector<std::vector<double>> contributions;  // [environment][walk] at albedo rho
};

// First hit of the ray (o, d) with the floor or the wall: the normal of the plane hit, or none.
bool hitPlanes(const Eigen::Vector3d& o, const Eigen::Vector3d& d, Eigen::Vector3d* at,
               Eigen::Vector3d* normal) {
  double best = INFINITY;
  if (d.y() < 0.0) {  // the floor
    const double t = -o.y() / d.y();
    const Eigen::Vector3d p = o + t * d;
    if (t > 1e-9 && p.x() >= 0.0 && p.x() <= kExtent && std::abs(p.z()) <= kExtent) {
      best = t;
      *normal = Eigen::Vector3d::UnitY();
    }
  }
  if (d.x() < 0.0) {  // the wall
    const double t = -o.x() / d.x();
    const Eigen::Vector3d p = o + t * d;
    if (t > 1e-9 && t < best && p.y() >= 0.0 && p.y() <= kExtent && std::abs(p.z()) <= kExtent) {
      best = t;
      *normal = Eigen::Vector3d::UnitX();
    }
  }
  if (std::isinf(best)) return false;
  *at = o + best * d;
  return true;
}

double radiance(const ShVector& sh, const Eigen::Vector3d& d) {
  double basis[kShCoefficients];
  shBasis(d.x(), d.y(), d.z(), basis);
  double sum = 0.0;
  for (int i = 0; i < kShCoefficients; ++i) sum += sh[i] * basis[i];
  return sum;
}

BruteForce bruteForce(const std::vector<Environment>& envs, double rho, int walks) {
  std::mt19937_64 rng(20261206);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  BruteForce out;
  out.contributions.assign(envs.size(), std::vector<double>(walks, 0.0));
  for (int w = 0; w < walks; ++w) {
    Eigen::Vector3d x(kDistance, 0.0, 0.0);
    Eigen::Vector3d n = Eigen::Vector3d::UnitY();
    double weight = 1.0;
    for (int k = 0; k <= kBounces; ++k) {
      // Cosine direction about n (Malley: a uniform disk point lifted).
      const double r = std::sqrt(uniform(rng));
      const double phi = 2.0 * kPi * uniform(rng);
      const Eigen::Vector3d t =
          std::abs(n.x()) > 0.5 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
      const Eigen::Vector3d a = n.cross(t).normalized();
      const Eigen::Vector3d b = n.cross(a);
      const Eigen::Vector3d d = (r * std::cos(phi) * a + r * std::sin(phi) * b +
                                 std::sqrt(std::max(0.0, 1.0 - r * r)) * n)
                                    .normalized();
      Eigen::Vector3d at;
      Eigen::Vector3d normal;
      if (!hitPlanes(x, d, &at, &normal)) {
        for (std::size_t e = 0; e < envs.size(); ++e)
          out.contributions[e][w] = weight * radiance(envs[e].sh, d);
        break;
      }
      x = at;
      n = normal;
      weight *= rho;
    }
  }
  return out;
}

// The sweep's estimate: transfer T_k from countEscapes, G = Σ_k ρ^k ⟨T_k, L⟩; and A.
struct SweepEstimate {
  std::vector<double> transfer;  // 9(K + 1), divided by the walks
  double A = 0.0;
};

SweepEstimate sweepEstimate(int streams, int spp) {
  const Scene scene = floorAndWall();
  const EmbreeTracer tracer(scene);
  WalkSettings settings;
  settings.spp = spp;
  settings.bounces = kBounces;
  SurfaceHit start;
  start.position = Eigen::Vector3f(kDistance, 0.0f, 0.0f);
  start.normal = Eigen::Vector3f::UnitY();
  SweepEstimate e;
  e.transfer.assign(kShCoefficients * (kBounces + 1), 0.0);
  std::vector<std::uint32_t> counts(2 * (kBounces + 1));
  WalkScratch scratch;
  for (int s = 0; s < streams; ++s) {
    countEscapes(tracer, start, settings, static_cast<std::uint64_t>(s), counts.data(), &scratch,
                 nullptr, nullptr, e.transfer.data());
  }
  const double walks = static_cast<double>(streams) * spp;
  for (double& v : e.transfer) v /= walks;
  e.A = (counts[0] + counts[kBounces + 1]) / walks;
  return e;
}

TEST(WallAnchor, SweepTransferMatchesBruteForceUnderEveryClass) {
  const int streams = 64;
  const int spp = 1024;
  const SweepEstimate sweep = sweepEstimate(streams, spp);
  const double n_sweep = static_cast<double>(streams) * spp;
  // A = 1/2 exactly; stratified walks: at most the binomial SE.
  EXPECT_NEAR(sweep.A, 0.5, 4.0 * std::sqrt(0.25 / n_sweep));
  std::vector<Environment> envs;
  for (const std::string& name : environmentClasses()) envs.push_back(builtInEnvironment(name));
  const int walks = 200000;
  for (double rho : {0.5, 0.8}) {
    const BruteForce brute = bruteForce(envs, rho, walks);
    for (std::size_t e = 0; e < envs.size(); ++e) {
      double g = 0.0;
      for (int k = kBounces; k >= 0; --k) {
        double dot = 0.0;
        for (int i = 0; i < kShCoefficients; ++i)
          dot += sweep.transfer[kShCoefficients * k + i] * envs[e].sh[i];
        g = g * rho + dot;
      }
      double mean = 0.0;
      double squares = 0.0;
      for (double c : brute.contributions[e]) {
        mean += c;
        squares += c * c;
      }
      mean /= walks;
      const double sigma = std::sqrt(std::max(0.0, squares / walks - mean * mean));
      // The sweep's walks have at most the brute force's per-walk variance (stratification).
      const double se = sigma * std::sqrt(1.0 / walks + 1.0 / n_sweep);
      EXPECT_NEAR(g, mean, 4.0 * se) << envs[e].name << " rho " << rho;
      // The engine's product: open floor (1 for every class) × Eq. 10 at A = 1/2.
      std::printf(
          "wall anchor %-8s rho %.1f: sweep G %.4f, brute force %.4f +- %.4f, "
          "Eq. 10 product %.4f\n",
          envs[e].name.c_str(), rho, g, mean, sigma / std::sqrt(walks),
          evalMultiBounce(kPaperCoeffs, 0.5, rho));
    }
  }
}

}  // namespace
}  // namespace gtbake
