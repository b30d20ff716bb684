#include "sweep/escape_walk.h"

#include <cmath>
#include <vector>

#include "common/rng.h"

namespace gtbake {

namespace {

constexpr float kQuarterPi = 0.785398163397448309616f;  // π/4, the concentric map's wedge angle

// Columns of the first-bounce stratification grid: the largest divisor of n not above √n.
int gridColumns(int n) {
  int a = static_cast<int>(std::sqrt(static_cast<double>(n)));
  while (a > 1 && n % a != 0) --a;
  return a;
}

}  // namespace

Eigen::Vector3f cosineDirection(const Eigen::Vector3f& n, float u0, float u1) {
  // Concentric map: the disk point is (r cos φ, r sin φ) with φ = π/4·t, |t| ≤ 1 in the first
  // wedge pair, and (r sin φ, r cos φ) (φ' = π/2 − φ) in the second; signed r covers the opposite
  // wedges. So only sin and cos on [−π/4, π/4] are needed: Taylor polynomials to x⁹ and x¹⁰,
  // whose truncation errors (< 2e-9 and 1e-10) lie below float rounding. Written with selects
  // rather than branches: this runs once per ray (bench_sweep).
  const float sx = 2.0f * u0 - 1.0f;
  const float sy = 2.0f * u1 - 1.0f;
  const bool first = std::fabs(sx) > std::fabs(sy);
  const float r = first ? sx : sy;  // also the denominator of t; r = 0 only at the disk centre
  const float x = r != 0.0f ? kQuarterPi * ((first ? sy : sx) / r) : 0.0f;
  const float x2 = x * x;
  const float sin_x =
      x * (1.0f + x2 * (-1.0f / 6 + x2 * (1.0f / 120 + x2 * (-1.0f / 5040 + x2 / 362880))));
  const float cos_x =
      1.0f +
      x2 * (-0.5f + x2 * (1.0f / 24 + x2 * (-1.0f / 720 + x2 * (1.0f / 40320 - x2 / 3628800))));
  const float dx = r * (first ? cos_x : sin_x);
  const float dy = r * (first ? sin_x : cos_x);
  const float h = 1.0f - dx * dx - dy * dy;
  const float dz = std::sqrt(h > 0.0f ? h : 0.0f);
  // Orthonormal basis (t, s, n) (Duff et al. 2017, "Building an orthonormal basis, revisited").
  // The result is unit length to float rounding; Embree needs no normalisation.
  const float sign = n.z() >= 0.0f ? 1.0f : -1.0f;
  const float a = -1.0f / (sign + n.z());
  const float b = n.x() * n.y() * a;
  const Eigen::Vector3f t(1.0f + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  const Eigen::Vector3f s(b, sign + n.y() * n.y() * a, -n.y());
  return dx * t + dy * s + dz * n;
}

WalkSampler::WalkSampler(const WalkSettings& settings, std::uint64_t stream)
    : rng_(settings.seed, stream), stratify_(settings.stratify_first_bounce) {
  const int half = settings.spp / 2;
  columns_ = gridColumns(half);
  rows_ = half / columns_;
}

Eigen::Vector3f WalkSampler::direction(const Eigen::Vector3f& normal, int s, int k) const {
  // Counter (sample s, block k): the draws of bounce k of walk s.
  const auto u = rng_.uniform4(static_cast<std::uint64_t>(s), static_cast<std::uint32_t>(k));
  float u0 = u[0];
  float u1 = u[1];
  if (k == 0 && stratify_) {
    const int t = s >> 1;  // index within the half-sample estimate: cell t of the grid
    u0 = (static_cast<float>(t % columns_) + u0) / static_cast<float>(columns_);
    u1 = (static_cast<float>(t / columns_) + u1) / static_cast<float>(rows_);
  }
  return cosineDirection(normal, u0, u1);
}

namespace {

std::uint64_t countEscapesSingle(const EmbreeTracer& tracer, const SurfaceHit& start,
                                 const WalkSettings& settings, const WalkSampler& sampler,
                                 std::uint32_t* counts) {
  const int bounces = settings.bounces;
  std::uint64_t rays = 0;
  for (int s = 0; s < settings.spp; ++s) {
    std::uint32_t* half_counts = counts + (s & 1) * (bounces + 1);
    SurfaceHit at = start;
    for (int k = 0; k <= bounces; ++k) {
      const Ray ray{tracer.offsetOrigin(at), sampler.direction(at.normal, s, k)};
      ++rays;
      if (k == bounces) {
        // The last counted segment: only whether it escapes matters.
        if (!tracer.occluded(ray, settings.radius)) ++half_counts[k];
        break;
      }
      if (!tracer.intersect(ray, settings.radius, &at)) {
        ++half_counts[k];
        break;
      }
    }
  }
  return rays;
}

std::uint64_t countEscapesStream(const EmbreeTracer& tracer, const SurfaceHit& start,
                                 const WalkSettings& settings, const WalkSampler& sampler,
                                 std::uint32_t* counts, WalkScratch* scratch) {
  const int bounces = settings.bounces;
  std::vector<SurfaceHit>& at = scratch->at;
  std::vector<int>& alive = scratch->alive;
  std::vector<int>& next = scratch->next;
  std::vector<RTCRayHit>& rays = scratch->rays;
  at.assign(static_cast<std::size_t>(settings.spp), start);
  alive.resize(static_cast<std::size_t>(settings.spp));
  for (int s = 0; s < settings.spp; ++s) alive[s] = s;
  rays.resize(alive.size());
  std::uint64_t traced = 0;
  for (int k = 0; k <= bounces && !alive.empty(); ++k) {
    const unsigned m = static_cast<unsigned>(alive.size());
    for (unsigned i = 0; i < m; ++i) {
      const SurfaceHit& from = at[alive[i]];
      rays[i] =
          makeRayHit(Ray{tracer.offsetOrigin(from), sampler.direction(from.normal, alive[i], k)},
                     settings.radius);
    }
    traced += m;
    if (k == bounces) {
      // The last counted segment: only whether it escapes matters.
      tracer.occludedStream(rays.data(), m);
      for (unsigned i = 0; i < m; ++i) {
        if (rays[i].ray.tfar >= 0.0f) ++counts[(alive[i] & 1) * (bounces + 1) + k];
      }
      break;
    }
    tracer.intersectStream(rays.data(), m);
    next.clear();
    for (unsigned i = 0; i < m; ++i) {
      if (rays[i].hit.geomID == RTC_INVALID_GEOMETRY_ID) {
        ++counts[(alive[i] & 1) * (bounces + 1) + k];
      } else {
        at[alive[i]] = tracer.surfaceHit(rays[i]);
        next.push_back(alive[i]);
      }
    }
    alive.swap(next);
  }
  return traced;
}

}  // namespace

std::uint64_t countEscapes(const EmbreeTracer& tracer, const SurfaceHit& start,
                           const WalkSettings& settings, std::uint64_t stream,
                           std::uint32_t* counts, WalkScratch* scratch) {
  const WalkSampler sampler(settings, stream);
  return settings.streams ? countEscapesStream(tracer, start, settings, sampler, counts, scratch)
                          : countEscapesSingle(tracer, start, settings, sampler, counts);
}

}  // namespace gtbake
