// Embree 3 ray queries over one Scene: the visibility oracle V(x, ω) of docs/sweep.md §1.
//
// The Scene's triangles go into one Embree triangle geometry whose vertex and index buffers are
// shared with this object (no copy inside Embree). The BVH is built with
// RTC_SCENE_FLAG_ROBUST (watertight traversal and intersection: rays that graze a shared edge of
// a closed box never leak to the sky) and RTC_BUILD_QUALITY_HIGH (spatial-split SAH BVH: the
// scenes are static and each is traced with tens of millions of incoherent rays, so a slower,
// better build pays back many times; docs/sweep.md has the build times). The build runs inside a
// one-thread TBB arena so the BVH, and with it every tie between equally near triangles, is the
// same for any --threads value.
//
// Surfaces are two-sided (docs/sweep.md §1): a hit reports the geometric normal flipped to the side
// the ray came from, and every secondary ray leaves from the hit point pushed off that side by
// kRayOffsetRelative × m (see there), with tnear = 0.
#pragma once

#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace gtbake {

// A ray leaves its origin after a push of kRayOffsetRelative × m along the oriented normal, m the
// larger of the hit triangle's largest |vertex coordinate| (≥ |x|∞, as x lies in the triangle)
// and |o|∞ + t of the ray o + t·d that found x. Why this size: the triangle's plane, Embree's
// watertight intersection and the hit point o + t·d carry errors of a few float ulps of those
// magnitudes (2^-23 ≈ 1.2e-7 relative); 1e-5 is ~100 ulps, so a ray never re-hits the surface it
// leaves. Yet for features within 10 m of the origin, reached by rays ≤ 10 m long, the push is
// ≤ 0.2 mm, far below every feature of the seven scenes (≥ 1 cm): the bias it adds to A at
// distance d from a concave edge is of order push/d, < 2e-3 beyond 0.1 m. Why not relative to the
// scene's bounding box: the generated grounds reach 10 km, which would push rays 0.28 m
// (tests/sweep caught exactly that); the coordinates that carry the error set the scale.
inline constexpr float kRayOffsetRelative = 1e-5f;  // dimensionless, relative to m

struct SurfaceHit {
  Eigen::Vector3f position;  // o + t·d of the ray that found it
  Eigen::Vector3f normal;    // unit geometric normal facing the incoming ray
  float scale = 0.0f;        // m of kRayOffsetRelative (0: use |x|∞ alone)
  float t = 0.0f;            // distance along the (unit) ray that found it
};

struct Ray {
  Eigen::Vector3f origin;
  Eigen::Vector3f direction;  // unit length
};

// Scalar kernels behind surfaceHit and offsetOrigin, inline so the walks' stream loop
// (escape_walk.cpp) vectorizes them; both traversals use them, so they agree bit for bit.
inline float maxAbs3(float x, float y, float z) {
  const float ax = x < 0.0f ? -x : x;
  const float ay = y < 0.0f ? -y : y;
  const float az = z < 0.0f ? -z : z;
  const float m = ax > ay ? ax : ay;
  return m > az ? m : az;
}

// The hit of the ray o + t·d on a triangle with (unnormalised) geometric normal g and largest
// |vertex coordinate| tri_scale: position o + t·d, unit normal facing the ray, offset scale
// max(tri_scale, |o|∞ + t) (see kRayOffsetRelative).
inline void hitFrame(const float o[3], const float d[3], float t, const float g[3], float tri_scale,
                     float p[3], float n[3], float* scale) {
  for (int c = 0; c < 3; ++c) p[c] = o[c] + t * d[c];
  const float reach = maxAbs3(o[0], o[1], o[2]) + t;
  *scale = tri_scale > reach ? tri_scale : reach;
  const float length = __builtin_sqrtf(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  // Two-sided surface: reflect on the side the ray arrived from.
  const bool facing = g[0] * d[0] + g[1] * d[1] + g[2] * d[2] > 0.0f;
  const float signed_length = facing ? -length : length;
  for (int c = 0; c < 3; ++c) n[c] = g[c] / signed_length;
}

// The secondary-ray origin x + ε·n, ε = kRayOffsetRelative · max(scale, |x|∞).
inline void offsetAlongNormal(const float p[3], const float n[3], float scale, float origin[3]) {
  const float m = maxAbs3(p[0], p[1], p[2]);
  const float offset = kRayOffsetRelative * (scale > m ? scale : m);
  for (int c = 0; c < 3; ++c) origin[c] = p[c] + offset * n[c];
}

class EmbreeTracer {
 public:
  // Throws gtbake::Error if the scene has no triangles or an index is out of range.
  // `quality` and `extra_flags` (added to RTC_SCENE_FLAG_ROBUST) only for bench/sweep's choice
  // of the build (docs/cluster.md, "Scale"); the sweep uses the defaults.
  explicit EmbreeTracer(const Scene& scene, RTCBuildQuality quality = RTC_BUILD_QUALITY_HIGH,
                        RTCSceneFlags extra_flags = RTC_SCENE_FLAG_NONE);
  ~EmbreeTracer();
  EmbreeTracer(const EmbreeTracer&) = delete;
  EmbreeTracer& operator=(const EmbreeTracer&) = delete;

  // Nearest hit with t in [0, tfar]; false if the ray reaches tfar without hitting anything.
  bool intersect(const Ray& ray, float tfar, SurfaceHit* hit) const;
  // True if anything lies along the ray within [0, tfar].
  bool occluded(const Ray& ray, float tfar) const;

  // Stream forms (rtcIntersect1M / rtcOccluded1M) over rays made by makeRayHit. A miss leaves
  // hit.geomID = RTC_INVALID_GEOMETRY_ID; an occluded ray gets tfar = −∞.
  void intersectStream(RTCRayHit* rays, unsigned count) const;
  void occludedStream(RTCRayHit* rays, unsigned count) const;  // sets only rays[i].ray.tfar
  // The hit of a ray that intersectStream found to hit something.
  SurfaceHit surfaceHit(const RTCRayHit& rayhit) const;

  // The secondary-ray origin for a walk leaving `hit` (see kRayOffsetRelative).
  Eigen::Vector3f offsetOrigin(const SurfaceHit& hit) const;

  // Largest |vertex coordinate| of triangle primID (the offset scale of hits on it).
  float triangleScale(unsigned prim_id) const { return triangle_scale_[prim_id]; }

  // The finished BVH; for benchmarks that replay rays through bare Embree calls.
  RTCScene handle() const { return scene_; }
  double buildSeconds() const { return build_seconds_; }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<float> vertices_;         // xyz per vertex, plus one float of padding for SSE loads
  std::vector<std::uint32_t> indices_;  // three per triangle
  std::vector<float> triangle_scale_;   // per triangle: largest |coordinate| of its vertices
  double build_seconds_ = 0.0;
};

// An Embree ray over [0, tfar] with no hit yet.
RTCRayHit makeRayHit(const Ray& ray, float tfar);

// A segment in a ray slot whose constant fields (tnear, time, mask, id, flags, instID) are set:
// origin, direction, [0, tfar], no hit yet; everything else as makeRayHit left it.
inline void setRay(RTCRayHit* rh, float ox, float oy, float oz, float dx, float dy, float dz,
                   float tfar) {
  rh->ray.org_x = ox;
  rh->ray.org_y = oy;
  rh->ray.org_z = oz;
  rh->ray.dir_x = dx;
  rh->ray.dir_y = dy;
  rh->ray.dir_z = dz;
  rh->ray.tfar = tfar;
  rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
}

// The primary ray of pixel (i, j) of a width×height image (docs/sweep.md §1, scene.h conventions):
// through the image-plane point ((i + 0.5)/width, (j + 0.5)/height), j = 0 the top row, aspect
// width/height.
Ray cameraRay(const PerspectiveCamera& camera, int i, int j, int width, int height);

}  // namespace gtbake
