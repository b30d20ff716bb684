#include "sweep/embree_tracer.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <string>

#include "common/error.h"

namespace gtbake {

namespace {

// Embree picks its traversal kernels for the CPU it runs on, and kernels of different widths may
// settle a ray that grazes a shared edge differently. Capping them at AVX2 gives every x86-64 CPU
// with AVX2 (AVX-512 ones included) the same kernels, so the same sweep bytes
// (docs/reproducibility.md, "What can differ on another machine").
constexpr const char* kEmbreeDeviceConfig = "max_isa=avx2";

// Embree's own message for the first error on a device, set by the device's error function
// (rtcSetDeviceErrorFunction) and turned into a gtbake::Error by throwOnDeviceError.
std::mutex g_embree_error_mutex;
std::string g_embree_error;

void recordEmbreeError(void*, RTCError code, const char* message) {
  std::lock_guard<std::mutex> lock(g_embree_error_mutex);
  if (g_embree_error.empty()) {
    g_embree_error = std::string(message != nullptr ? message : "no message") + " (error code " +
                     std::to_string(static_cast<int>(code)) + ")";
  }
}

void throwOnDeviceError(RTCDevice device, const char* what) {
  const RTCError code = rtcGetDeviceError(device);
  std::lock_guard<std::mutex> lock(g_embree_error_mutex);
  if (code != RTC_ERROR_NONE || !g_embree_error.empty()) {
    const std::string message = g_embree_error.empty()
                                    ? "error code " + std::to_string(static_cast<int>(code))
                                    : g_embree_error;
    g_embree_error.clear();
    throw Error(std::string("Embree failed to ") + what + ": " + message);
  }
}

}  // namespace

EmbreeTracer::EmbreeTracer(const Scene& scene, RTCBuildQuality quality, RTCSceneFlags extra_flags) {
  if (scene.triangles.empty()) throw Error("scene '" + scene.name + "' has no triangles");
  const std::size_t vertex_count = scene.positions.size();
  vertices_.resize(3 * vertex_count + 1, 0.0f);
  for (std::size_t v = 0; v < vertex_count; ++v) {
    const Eigen::Vector3f& p = scene.positions[v];
    if (!p.allFinite()) throw Error("scene '" + scene.name + "' has a non-finite vertex");
    for (int c = 0; c < 3; ++c) vertices_[3 * v + c] = p[c];
  }
  indices_.reserve(3 * scene.triangles.size());
  triangle_scale_.reserve(scene.triangles.size());
  for (const auto& t : scene.triangles) {
    float scale = 0.0f;
    for (std::uint32_t index : t) {
      if (index >= vertex_count) {
        throw Error("scene '" + scene.name + "' has a triangle index out of range");
      }
      indices_.push_back(index);
      scale = std::max(scale, scene.positions[index].cwiseAbs().maxCoeff());
    }
    triangle_scale_.push_back(scale);
  }

  const auto start = std::chrono::steady_clock::now();
  device_ = rtcNewDevice(kEmbreeDeviceConfig);
  if (device_ == nullptr) {
    throw Error("Embree could not create a device (error code " +
                std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  }
  rtcSetDeviceErrorFunction(device_, recordEmbreeError, nullptr);
  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, static_cast<RTCSceneFlags>(RTC_SCENE_FLAG_ROBUST | extra_flags));
  rtcSetSceneBuildQuality(scene_, quality);
  RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(geometry, quality);
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                             vertices_.data(), 0, 3 * sizeof(float), vertex_count);
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices_.data(),
                             0, 3 * sizeof(std::uint32_t), scene.triangles.size());
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene_, geometry);
  rtcReleaseGeometry(geometry);
  throwOnDeviceError(device_, "set up the geometry");
  // One worker for the build: the BVH (and so tie-breaking) must not depend on --threads.
  tbb::task_arena single_thread(1);
  single_thread.execute([&] { rtcCommitScene(scene_); });
  throwOnDeviceError(device_, "build the BVH");
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

EmbreeTracer::~EmbreeTracer() {
  if (scene_ != nullptr) rtcReleaseScene(scene_);
  if (device_ != nullptr) rtcReleaseDevice(device_);
}

RTCRayHit makeRayHit(const Ray& ray, float tfar) {
  RTCRayHit rh;
  rh.ray.tnear = 0.0f;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  setRay(&rh, ray.origin.x(), ray.origin.y(), ray.origin.z(), ray.direction.x(), ray.direction.y(),
         ray.direction.z(), tfar);
  return rh;
}

bool EmbreeTracer::intersect(const Ray& ray, float tfar, SurfaceHit* hit) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = makeRayHit(ray, tfar);
  rtcIntersect1(scene_, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  *hit = surfaceHit(rh);
  return true;
}

bool EmbreeTracer::occluded(const Ray& ray, float tfar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = makeRayHit(ray, tfar);
  rtcOccluded1(scene_, &context, &rh.ray);
  return rh.ray.tfar < 0.0f;  // Embree sets tfar = -inf on a hit
}

void EmbreeTracer::intersectStream(RTCRayHit* rays, unsigned count) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1M(scene_, &context, rays, count, sizeof(RTCRayHit));
}

void EmbreeTracer::occludedStream(RTCRayHit* rays, unsigned count) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  // RTCRayHit starts with its RTCRay, so a stride of sizeof(RTCRayHit) walks the rays in place.
  rtcOccluded1M(scene_, &context, &rays[0].ray, count, sizeof(RTCRayHit));
}

SurfaceHit EmbreeTracer::surfaceHit(const RTCRayHit& rh) const {
  const float o[3] = {rh.ray.org_x, rh.ray.org_y, rh.ray.org_z};
  const float d[3] = {rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z};
  const float g[3] = {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
  float p[3];
  float n[3];
  SurfaceHit hit;
  // Along the ray: no vertex fetch. Its error, a few ulps of max(|origin|, t), is covered by
  // folding |origin|∞ + t into the offset scale next to the triangle's own coordinates.
  hitFrame(o, d, rh.ray.tfar, g, triangle_scale_[rh.hit.primID], p, n, &hit.scale);
  hit.position = Eigen::Vector3f(p[0], p[1], p[2]);
  hit.normal = Eigen::Vector3f(n[0], n[1], n[2]);
  hit.t = rh.ray.tfar;
  return hit;
}

Eigen::Vector3f EmbreeTracer::offsetOrigin(const SurfaceHit& hit) const {
  const float p[3] = {hit.position.x(), hit.position.y(), hit.position.z()};
  const float n[3] = {hit.normal.x(), hit.normal.y(), hit.normal.z()};
  float origin[3];
  offsetAlongNormal(p, n, hit.scale, origin);
  return Eigen::Vector3f(origin[0], origin[1], origin[2]);
}

Ray cameraRay(const PerspectiveCamera& camera, int i, int j, int width, int height) {
  const double tan_half = std::tan(0.5 * camera.yfov);
  const double aspect = static_cast<double>(width) / static_cast<double>(height);
  const double sx = (2.0 * (i + 0.5) / width - 1.0) * tan_half * aspect;
  const double sy = (1.0 - 2.0 * (j + 0.5) / height) * tan_half;
  const Eigen::Vector3d d =
      (sx * camera.basis.col(0) + sy * camera.basis.col(1) - camera.basis.col(2)).normalized();
  return Ray{camera.position.cast<float>(), d.cast<float>()};
}

}  // namespace gtbake
