#include "sweep/escape_walk.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/spherical_harmonics.h"
#include "sweep/cosine_direction.h"
#include "sweep/philox_lanes.h"

namespace gtbake {

std::uint32_t viewStreamKey(const std::string& view_name) {
  std::uint32_t h = 2166136261u;  // FNV-1a offset basis and prime (32 bit)
  for (unsigned char c : view_name) h = (h ^ c) * 16777619u;
  return h;
}

Eigen::Vector3f cosineDirection(const Eigen::Vector3f& n, float u0, float u1) {
  const float normal[3] = {n.x(), n.y(), n.z()};
  float t[3];
  float s[3];
  float d[3];
  tangentBasis(normal[0], normal[1], normal[2], t, s);
  cosineDirection(normal, t, s, u0, u1, d);
  return Eigen::Vector3f(d[0], d[1], d[2]);
}

WalkSampler::WalkSampler(const WalkSettings& settings, std::uint64_t stream)
    : rng_(settings.seed, stream),
      stratify_(settings.stratify_first_bounce),
      grid_(std::max(1, settings.spp / 2)) {}

std::array<std::uint32_t, 4> WalkSampler::blockWords(int s, int k) const {
  return rng_.words(static_cast<std::uint64_t>(s), static_cast<std::uint32_t>(k >> 1));
}

Eigen::Vector3f WalkSampler::direction(const Eigen::Vector3f& normal, int s, int k,
                                       const std::array<std::uint32_t, 4>& words) const {
  float u0 = wordToUniform(words[2 * (k & 1)]);
  float u1 = wordToUniform(words[2 * (k & 1) + 1]);
  if (k == 0 && stratify_) {
    u0 = stratum(grid_.column(s), u0, grid_.columns());
    u1 = stratum(grid_.row(s), u1, grid_.rows());
  }
  return cosineDirection(normal, u0, u1);
}

namespace {

// Adds a first-bounce direction to the bent-normal sum, if one is kept.
inline void addDirection(double* sum, float x, float y, float z) {
  if (sum == nullptr) return;
  sum[0] += x;
  sum[1] += y;
  sum[2] += z;
}

// Adds the SH basis at the escape direction of a walk that escapes after k bounces to the transfer
// sums of bounce k (docs/sweep.md, "Transfer"), if they are kept: in double, in sample order per k
// in both traversals (the stream keeps its walks in sample order), so both give the same bits.
inline void addTransfer(double* sums, int k, float x, float y, float z) {
  if (sums == nullptr) return;
  double basis[kShCoefficients];
  shBasis(x, y, z, basis);
  double* to = sums + k * kShCoefficients;
  for (int i = 0; i < kShCoefficients; ++i) to[i] += basis[i];
}

// Segment k of a walk of half h, alive at the G-buffer radii from index *near on, missed (t = ∞)
// or hit at distance t: every alive radius R < t counts an escape after k bounces and *near moves
// past it (radii ascend, so the radii a walk escaped at are always a prefix).
inline void addNearEscapes(std::uint32_t* near_counts, const std::vector<float>& radii, int h,
                           int k, int bounces, float t, std::int32_t* near) {
  if (near_counts == nullptr) return;
  const std::int32_t n = static_cast<std::int32_t>(radii.size());
  for (; *near < n && t > radii[*near]; ++*near) {
    ++near_counts[(2 * *near + h) * (bounces + 1) + k];
  }
}

// How far the last segment of a walk still alive at a G-buffer radius is traced again for its hit
// distance: the largest radius (within the sky radius).
inline float nearLimit(const WalkSettings& settings) {
  return std::min(settings.gbuffer_radii.back(), settings.radius);
}

void resizeScratch(WalkScratch* w, int spp, const WalkSampler& sampler) {
  const std::size_t n = static_cast<std::size_t>(spp);
  if (w->walk.size() < n) {
    w->walk.resize(n);
    for (auto& v : w->words) v.resize(n);
    for (auto& v : w->u) v.resize(n);
    for (int c = 0; c < 3; ++c) {
      w->from[c].resize(n);
      w->along[c].resize(n);
      w->ng[c].resize(n);
      w->origin[c].resize(n);
      w->direction[c].resize(n);
    }
    w->t.resize(n);
    w->near.resize(n);
    w->tri_scale.resize(n);
    // The fields Embree never writes are set once here (makeRayHit's values); setRay fills the
    // rest for every segment.
    w->rays.assign(n, makeRayHit(Ray{Eigen::Vector3f::Zero(), Eigen::Vector3f::UnitZ()}, 0.0f));
  }
  if (w->cell_count != spp || w->cell_columns != sampler.grid().columns()) {
    w->cell[0].resize(n);
    w->cell[1].resize(n);
    for (int s = 0; s < spp; ++s) {
      w->cell[0][s] = sampler.grid().column(s);
      w->cell[1][s] = sampler.grid().row(s);
    }
    w->cell_count = spp;
    w->cell_columns = sampler.grid().columns();
  }
}

// Bounce k's (u0, u1) for the m walks alive, from the block's words (stratified at k = 0).
void bounceUniforms(WalkScratch* w, int m, int k, const WalkSampler& sampler) {
  const std::uint32_t* __restrict a = w->words[2 * (k & 1)].data();
  const std::uint32_t* __restrict b = w->words[2 * (k & 1) + 1].data();
  float* __restrict u0 = w->u[0].data();
  float* __restrict u1 = w->u[1].data();
  for (int i = 0; i < m; ++i) {
    u0[i] = wordToUniform(a[i]);
    u1[i] = wordToUniform(b[i]);
  }
  if (k == 0 && sampler.stratified()) {
    // Every walk is alive at k = 0, so slot i is sample i.
    const float* __restrict cu = w->cell[0].data();
    const float* __restrict cv = w->cell[1].data();
    const int columns = sampler.grid().columns();
    const int rows = sampler.grid().rows();
    for (int i = 0; i < m; ++i) {
      u0[i] = stratum(cu[i], u0[i], columns);
      u1[i] = stratum(cv[i], u1[i], rows);
    }
  }
}

// The first segments: one origin and basis for every walk.
GTBAKE_AVX2_CLONES void firstDirectionsKernel(int m, const float n[3], const float t[3],
                                              const float s[3], const float* __restrict u0,
                                              const float* __restrict u1, float* __restrict dx,
                                              float* __restrict dy, float* __restrict dz) {
  for (int i = 0; i < m; ++i) {
    float d[3];
    cosineDirection(n, t, s, u0[i], u1[i], d);
    dx[i] = d[0];
    dy[i] = d[1];
    dz[i] = d[2];
  }
}

void firstDirections(WalkScratch* w, int m, const float n[3]) {
  float t[3];
  float s[3];
  tangentBasis(n[0], n[1], n[2], t, s);
  firstDirectionsKernel(m, n, t, s, w->u[0].data(), w->u[1].data(), w->direction[0].data(),
                        w->direction[1].data(), w->direction[2].data());
}

// Later segments: each walk leaves its own last hit (hitFrame, offsetAlongNormal, as the one-ray
// path's surfaceHit and offsetOrigin). Arrays as restrict parameters, so the loop vectorizes
// without run-time alias checks.
GTBAKE_AVX2_CLONES void nextSegmentsKernel(
    int m, const float* __restrict fx, const float* __restrict fy, const float* __restrict fz,
    const float* __restrict ax, const float* __restrict ay, const float* __restrict az,
    const float* __restrict th, const float* __restrict gx, const float* __restrict gy,
    const float* __restrict gz, const float* __restrict tri, const float* __restrict u0,
    const float* __restrict u1, float* __restrict ox, float* __restrict oy, float* __restrict oz,
    float* __restrict dx, float* __restrict dy, float* __restrict dz) {
  for (int i = 0; i < m; ++i) {
    const float o[3] = {fx[i], fy[i], fz[i]};
    const float a[3] = {ax[i], ay[i], az[i]};
    const float g[3] = {gx[i], gy[i], gz[i]};
    float p[3];
    float n[3];
    float scale;
    hitFrame(o, a, th[i], g, tri[i], p, n, &scale);
    float origin[3];
    offsetAlongNormal(p, n, scale, origin);
    float t[3];
    float s[3];
    tangentBasis(n[0], n[1], n[2], t, s);
    float d[3];
    cosineDirection(n, t, s, u0[i], u1[i], d);
    ox[i] = origin[0];
    oy[i] = origin[1];
    oz[i] = origin[2];
    dx[i] = d[0];
    dy[i] = d[1];
    dz[i] = d[2];
  }
}

void nextSegments(WalkScratch* w, int m) {
  nextSegmentsKernel(m, w->from[0].data(), w->from[1].data(), w->from[2].data(), w->along[0].data(),
                     w->along[1].data(), w->along[2].data(), w->t.data(), w->ng[0].data(),
                     w->ng[1].data(), w->ng[2].data(), w->tri_scale.data(), w->u[0].data(),
                     w->u[1].data(), w->origin[0].data(), w->origin[1].data(), w->origin[2].data(),
                     w->direction[0].data(), w->direction[1].data(), w->direction[2].data());
}

// Walk after walk, one rtcIntersect1 / rtcOccluded1 per segment. The first segments, which share
// one origin and basis, are made for all walks at once as in the stream traversal; later ones
// through surfaceHit, offsetOrigin and WalkSampler (the same kernels, so the same rays).
std::uint64_t countEscapesSingle(const EmbreeTracer& tracer, const SurfaceHit& start,
                                 const WalkSettings& settings, const WalkSampler& sampler,
                                 std::uint64_t stream, std::uint32_t* counts, WalkScratch* w,
                                 double* first_escape_sum, std::uint32_t* near_counts,
                                 double* transfer_sums) {
  const int bounces = settings.bounces;
  const int spp = settings.spp;
  resizeScratch(w, spp, sampler);
  for (int s = 0; s < spp; ++s) w->walk[s] = s;
  PhiloxLanes(settings.seed, stream)
      .words(w->walk.data(), spp, 0, w->words[0].data(), w->words[1].data(), w->words[2].data(),
             w->words[3].data());
  bounceUniforms(w, spp, 0, sampler);
  const float n0[3] = {start.normal.x(), start.normal.y(), start.normal.z()};
  firstDirections(w, spp, n0);
  const Eigen::Vector3f origin0 = tracer.offsetOrigin(start);
  std::uint64_t rays = 0;
  const std::vector<float>& radii = settings.gbuffer_radii;
  const std::int32_t near_end =
      near_counts == nullptr ? 0 : static_cast<std::int32_t>(radii.size());
  for (int s = 0; s < spp; ++s) {
    std::uint32_t* half_counts = counts + (s & 1) * (bounces + 1);
    std::int32_t near = 0;
    SurfaceHit at = start;
    std::array<std::uint32_t, 4> words = {w->words[0][s], w->words[1][s], w->words[2][s],
                                          w->words[3][s]};
    for (int k = 0; k <= bounces; ++k) {
      Ray ray;
      if (k == 0) {
        ray = Ray{origin0,
                  Eigen::Vector3f(w->direction[0][s], w->direction[1][s], w->direction[2][s])};
      } else {
        if ((k & 1) == 0) words = sampler.blockWords(s, k);
        ray = Ray{tracer.offsetOrigin(at), sampler.direction(at.normal, s, k, words)};
      }
      ++rays;
      const bool escaped = k == bounces ? !tracer.occluded(ray, settings.radius)
                                        : !tracer.intersect(ray, settings.radius, &at);
      if (escaped) {
        ++half_counts[k];
        addNearEscapes(near_counts, radii, s & 1, k, bounces, INFINITY, &near);
        if (k == 0)
          addDirection(first_escape_sum, ray.direction.x(), ray.direction.y(), ray.direction.z());
        addTransfer(transfer_sums, k, ray.direction.x(), ray.direction.y(), ray.direction.z());
        break;
      }
      if (k == bounces && near < near_end) {
        // The last segment again, for its hit distance (escape_walk.h, countEscapes).
        ++rays;
        at.t = tracer.intersect(ray, nearLimit(settings), &at) ? at.t : INFINITY;
      }
      addNearEscapes(near_counts, radii, s & 1, k, bounces, at.t, &near);
    }
  }
  return rays;
}

// The walks of the point's last segment K that hit something (unbounded: no escape) but are still
// alive at some G-buffer radius: that segment again up to nearLimit, one rtcIntersect1M, for its
// hit distance. Reads slots 0..m of the occluded stream; returns the rays traced.
std::uint64_t lastNearSegments(const EmbreeTracer& tracer, const WalkSettings& settings, int m,
                               std::uint32_t* near_counts, WalkScratch* w) {
  RTCRayHit* rays = w->rays.data();
  const std::int32_t near_end = static_cast<std::int32_t>(settings.gbuffer_radii.size());
  int n = 0;  // slot n ≤ i, so in place
  for (int i = 0; i < m; ++i) {
    if (rays[i].ray.tfar >= 0.0f || w->near[i] >= near_end) continue;
    w->walk[n] = w->walk[i];
    w->near[n] = w->near[i];
    setRay(&rays[n], w->origin[0][i], w->origin[1][i], w->origin[2][i], w->direction[0][i],
           w->direction[1][i], w->direction[2][i], nearLimit(settings));
    ++n;
  }
  if (n == 0) return 0;
  tracer.intersectStream(rays, static_cast<unsigned>(n));
  for (int i = 0; i < n; ++i) {
    const bool hit = rays[i].hit.geomID != RTC_INVALID_GEOMETRY_ID;
    addNearEscapes(near_counts, settings.gbuffer_radii, w->walk[i] & 1, settings.bounces,
                   settings.bounces, hit ? rays[i].ray.tfar : INFINITY, &w->near[i]);
  }
  return static_cast<std::uint64_t>(n);
}

// Bounce k's escapes among the m walks of the intersect stream: counted (unbounded and at every
// G-buffer radius they reach); the survivors' hits compacted to the front (slot alive ≤ i, so in
// place). Returns how many survive.
int countAndCompact(const EmbreeTracer& tracer, const WalkSettings& settings, int m, int k,
                    std::uint32_t* counts, double* first_escape_sum, std::uint32_t* near_counts,
                    double* transfer_sums, WalkScratch* w) {
  const int bounces = settings.bounces;
  const RTCRayHit* rays = w->rays.data();
  int alive = 0;
  for (int i = 0; i < m; ++i) {
    const RTCRayHit& rh = rays[i];
    const int h = w->walk[i] & 1;
    const bool escaped = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID;
    addNearEscapes(near_counts, settings.gbuffer_radii, h, k, bounces,
                   escaped ? INFINITY : rh.ray.tfar, &w->near[i]);
    if (escaped) {
      ++counts[h * (bounces + 1) + k];
      if (k == 0) addDirection(first_escape_sum, rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
      addTransfer(transfer_sums, k, rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
      continue;
    }
    w->walk[alive] = w->walk[i];
    w->near[alive] = w->near[i];
    w->words[2][alive] = w->words[2][i];
    w->words[3][alive] = w->words[3][i];
    w->from[0][alive] = rh.ray.org_x;
    w->from[1][alive] = rh.ray.org_y;
    w->from[2][alive] = rh.ray.org_z;
    w->along[0][alive] = rh.ray.dir_x;
    w->along[1][alive] = rh.ray.dir_y;
    w->along[2][alive] = rh.ray.dir_z;
    w->t[alive] = rh.ray.tfar;
    w->ng[0][alive] = rh.hit.Ng_x;
    w->ng[1][alive] = rh.hit.Ng_y;
    w->ng[2][alive] = rh.hit.Ng_z;
    w->tri_scale[alive] = tracer.triangleScale(rh.hit.primID);
    ++alive;
  }
  return alive;
}

// All walks of the point bounce by bounce (the estimator of escape_walk.h): per bounce the Philox
// words (even k; odd k uses the carried words 2, 3), the uniforms and the segments of every walk
// alive in vectorized loops, one rtcIntersect1M (rtcOccluded1M for segment K + 1), then the
// escapes counted per half and the survivors' hits compacted to the front.
std::uint64_t countEscapesStream(const EmbreeTracer& tracer, const SurfaceHit& start,
                                 const WalkSettings& settings, const WalkSampler& sampler,
                                 std::uint64_t stream, std::uint32_t* counts, WalkScratch* w,
                                 double* first_escape_sum, std::uint32_t* near_counts,
                                 double* transfer_sums) {
  const int bounces = settings.bounces;
  resizeScratch(w, settings.spp, sampler);
  const PhiloxLanes philox(settings.seed, stream);
  const float p0[3] = {start.position.x(), start.position.y(), start.position.z()};
  const float n0[3] = {start.normal.x(), start.normal.y(), start.normal.z()};
  float origin0[3];
  offsetAlongNormal(p0, n0, start.scale, origin0);
  int m = settings.spp;
  for (int s = 0; s < m; ++s) w->walk[s] = s;
  std::fill(w->near.begin(), w->near.begin() + m, 0);
  RTCRayHit* rays = w->rays.data();
  std::uint64_t traced = 0;
  for (int k = 0; k <= bounces && m > 0; ++k) {
    if ((k & 1) == 0) {
      philox.words(w->walk.data(), m, static_cast<std::uint32_t>(k >> 1), w->words[0].data(),
                   w->words[1].data(), w->words[2].data(), w->words[3].data());
    }
    bounceUniforms(w, m, k, sampler);
    const float* dx = w->direction[0].data();
    const float* dy = w->direction[1].data();
    const float* dz = w->direction[2].data();
    if (k == 0) {
      firstDirections(w, m, n0);
      for (int i = 0; i < m; ++i) {
        setRay(&rays[i], origin0[0], origin0[1], origin0[2], dx[i], dy[i], dz[i], settings.radius);
      }
    } else {
      nextSegments(w, m);
      const float* ox = w->origin[0].data();
      const float* oy = w->origin[1].data();
      const float* oz = w->origin[2].data();
      for (int i = 0; i < m; ++i) {
        setRay(&rays[i], ox[i], oy[i], oz[i], dx[i], dy[i], dz[i], settings.radius);
      }
    }
    traced += static_cast<std::uint64_t>(m);
    if (k == bounces) {
      // The last counted segment: only whether it escapes matters (and, for a walk still alive
      // at a G-buffer radius, where it hits: lastNearSegments).
      tracer.occludedStream(rays, static_cast<unsigned>(m));
      for (int i = 0; i < m; ++i) {
        if (rays[i].ray.tfar < 0.0f) continue;
        ++counts[(w->walk[i] & 1) * (bounces + 1) + k];
        addNearEscapes(near_counts, settings.gbuffer_radii, w->walk[i] & 1, k, bounces, INFINITY,
                       &w->near[i]);
        if (k == 0) addDirection(first_escape_sum, dx[i], dy[i], dz[i]);
        addTransfer(transfer_sums, k, dx[i], dy[i], dz[i]);
      }
      if (near_counts != nullptr) traced += lastNearSegments(tracer, settings, m, near_counts, w);
      break;
    }
    tracer.intersectStream(rays, static_cast<unsigned>(m));
    m = countAndCompact(tracer, settings, m, k, counts, first_escape_sum, near_counts,
                        transfer_sums, w);
  }
  return traced;
}

}  // namespace

std::uint64_t countEscapes(const EmbreeTracer& tracer, const SurfaceHit& start,
                           const WalkSettings& settings, std::uint64_t stream,
                           std::uint32_t* counts, WalkScratch* scratch, double* first_escape_sum,
                           std::uint32_t* near_counts, double* transfer_sums) {
  const WalkSampler sampler(settings, stream);
  return settings.streams
             ? countEscapesStream(tracer, start, settings, sampler, stream, counts, scratch,
                                  first_escape_sum, near_counts, transfer_sums)
             : countEscapesSingle(tracer, start, settings, sampler, stream, counts, scratch,
                                  first_escape_sum, near_counts, transfer_sums);
}

}  // namespace gtbake
