// bench_sweep_scale: the sweep on a generated glTF scene of 10³ … 10⁶+ triangles at 1920×1080
// (docs/cluster.md, "Scale"): glTF size and load time, Embree build time per build quality,
// tracing throughput, and the process's peak memory.
//
// The scene is a rough heightfield (a grid of n × n quads, 2n² triangles, ±1 m of summed sines
// over 40 × 40 m) with n × n / 64 boxes standing on it, seen at 35° from above, so that walks
// bounce between boxes and ground as in the production scenes the sweep is for. It is written
// as glTF and read back with readGltfScene, as `gtbake sweep` would.
//
// Usage:
//   bench_sweep_scale trace TRIANGLES QUALITY [WxH = 1920x1080] [spp = 2] [DIR = /tmp]
//       QUALITY: low | medium | high | high-compact. Builds, then traces every pixel
//       (traceEscapeImage, K = 3, no specular); one line of results.
//   bench_sweep_scale sweep TRIANGLES [WxH = 1920x1080] [spp = 2] [DIR = /tmp]
//       runSweep on the scene (what `gtbake sweep` does, EXR and all); one line of results.
// One configuration per process, so peak memory (getrusage) is that configuration's.
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "common/error.h"
#include "scene/mesh_builder.h"
#include "scene/scene.h"
#include "sweep/escape_image.h"
#include "sweep/sweep_command.h"

namespace gtbake {
namespace {

double peakMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

// User + system CPU seconds of the process so far: per CPU-second rates barely move with the load
// other processes put on the machine, wall-clock ones do.
double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// About `triangles` triangles: a heightfield of n² quads plus boxes (10 triangles each, no
// bottom) on every 8th vertex of every 8th row.
Scene makeScaleScene(long triangles) {
  const int n = std::max(4, static_cast<int>(std::sqrt(triangles / (2.0 + 10.0 / 64.0))));
  const float size = 40.0f;
  Scene scene;
  scene.name = "scale";
  auto height = [](float x, float z) {
    return 0.5f * std::sin(0.9f * x) * std::cos(0.7f * z) + 0.3f * std::sin(2.3f * x + 1.3f * z) +
           0.2f * std::sin(5.1f * z - 3.7f * x);
  };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const float x = size * (static_cast<float>(i) / n - 0.5f);
      const float z = size * (static_cast<float>(j) / n - 0.5f);
      scene.positions.emplace_back(x, height(x, z), z);
    }
  }
  auto vertex = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      scene.triangles.push_back({vertex(i, j), vertex(i, j + 1), vertex(i + 1, j)});
      scene.triangles.push_back({vertex(i + 1, j), vertex(i, j + 1), vertex(i + 1, j + 1)});
    }
  }
  const float cell = size / n;
  for (int j = 4; j < n; j += 8) {
    for (int i = 4; i < n; i += 8) {
      const float x = size * (static_cast<float>(i) / n - 0.5f);
      const float z = size * (static_cast<float>(j) / n - 0.5f);
      const float h = height(x, z);
      const float half = 2.0f * cell;
      const float top = h + 4.0f * cell * (1.0f + std::sin(0.37f * static_cast<float>(i * j)));
      const auto base = static_cast<std::uint32_t>(scene.positions.size());
      for (int k = 0; k < 8; ++k) {
        scene.positions.emplace_back(x + ((k & 1) ? half : -half), (k & 4) ? top : h - cell,
                                     z + ((k & 2) ? half : -half));
      }
      static constexpr std::uint32_t kFaces[10][3] = {{0, 4, 1}, {1, 4, 5}, {1, 5, 3}, {3, 5, 7},
                                                      {3, 7, 2}, {2, 7, 6}, {2, 6, 0}, {0, 6, 4},
                                                      {4, 6, 5}, {5, 6, 7}};
      for (const auto& f : kFaces)
        scene.triangles.push_back({base + f[0], base + f[1], base + f[2]});
    }
  }
  scene.camera = lookAt(Eigen::Vector3d(0.0, 14.0, 20.0), Eigen::Vector3d(0.0, 0.0, 0.0),
                        Eigen::Vector3d::UnitY(), 0.9);
  return scene;
}

std::pair<int, int> resolution(const char* text) {
  int w = 0;
  int h = 0;
  if (std::sscanf(text, "%dx%d", &w, &h) != 2) throw Error("bad resolution " + std::string(text));
  return {w, h};
}

int run(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: %s trace TRIANGLES QUALITY [WxH] [spp] [DIR] | "
                 "sweep TRIANGLES [WxH] [spp] [DIR]\n",
                 argv[0]);
    return 2;
  }
  const std::string mode = argv[1];
  const long triangles = std::atol(argv[2]);
  int arg = 3;
  std::string quality = "high";
  if (mode == "trace") quality = argc > arg ? argv[arg++] : "high";
  const auto [width, height] = resolution(argc > arg ? argv[arg++] : "1920x1080");
  const int spp = argc > arg ? std::atoi(argv[arg++]) : 2;
  const std::filesystem::path dir = argc > arg ? argv[arg++] : "/tmp";
  const std::filesystem::path gltf = dir / ("bench_scale_" + std::to_string(triangles) + ".gltf");

  auto t = std::chrono::steady_clock::now();
  writeGltfScene(gltf, makeScaleScene(triangles));
  const double write_seconds = secondsSince(t);
  t = std::chrono::steady_clock::now();
  const Scene scene = readGltfScene(gltf);
  const double load_seconds = secondsSince(t);
  const double gltf_mb =
      static_cast<double>(
          std::filesystem::file_size(gltf) +
          std::filesystem::file_size(std::filesystem::path(gltf).replace_extension(".bin"))) /
      1e6;

  if (mode == "sweep") {
    SweepOptions o;
    o.scenes = {gltf};
    o.out = dir / ("bench_scale_sweep_" + std::to_string(triangles));
    o.width = width;
    o.height = height;
    o.spp = spp;
    o.specular_roughness.clear();
    o.progress = false;
    const SweepResult r = runSweep(o);
    std::printf(
        "sweep triangles %zu res %dx%d spp %d: glTF %.1f MB (write %.2f s, load %.2f s), "
        "sweep %.2f s, %.1f Mrays, %.2f Mrays/s (incl. build and EXR), peak RSS %.0f MB\n",
        scene.triangles.size(), width, height, spp, gltf_mb, write_seconds, load_seconds, r.seconds,
        1e-6 * static_cast<double>(r.rays), 1e-6 * static_cast<double>(r.rays) / r.seconds,
        peakMegabytes());
    return 0;
  }
  RTCBuildQuality q = RTC_BUILD_QUALITY_HIGH;
  RTCSceneFlags flags = RTC_SCENE_FLAG_NONE;
  if (quality == "low") {
    q = RTC_BUILD_QUALITY_LOW;
  } else if (quality == "medium") {
    q = RTC_BUILD_QUALITY_MEDIUM;
  } else if (quality == "high-compact") {
    flags = RTC_SCENE_FLAG_COMPACT;
  } else if (quality != "high") {
    throw Error("QUALITY must be low, medium, high or high-compact");
  }
  const double before_build_mb = peakMegabytes();
  const EmbreeTracer tracer(scene, q, flags);
  const double bvh_mb = peakMegabytes() - before_build_mb;
  WalkSettings settings;
  settings.spp = spp;
  settings.specular_roughness.clear();
  settings.specular_spp = 0;
  settings.view_key = viewStreamKey(scene.name);
  const double cpu_start = cpuSeconds();
  const EscapeImage image =
      traceEscapeImage(tracer, scene.camera, width, height, settings, "", false);
  const double cpu = cpuSeconds() - cpu_start;
  std::printf(
      "trace triangles %zu quality %s res %dx%d spp %d: build %.2f s (1 thread), "
      "+%.0f MB peak at build, trace %.2f s, %.1f Mrays, %.2f Mrays/s, %.2f Mrays/CPU-s, "
      "unmasked %.3f, peak RSS %.0f MB\n",
      scene.triangles.size(), quality.c_str(), width, height, spp, tracer.buildSeconds(), bvh_mb,
      image.seconds, 1e-6 * static_cast<double>(image.rays),
      1e-6 * static_cast<double>(image.rays) / image.seconds,
      1e-6 * static_cast<double>(image.rays) / cpu,
      static_cast<double>(image.unmaskedPixels()) / (static_cast<double>(width) * height),
      peakMegabytes());
  return 0;
}

}  // namespace
}  // namespace gtbake

int main(int argc, char** argv) {
  try {
    return gtbake::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_sweep_scale: %s\n", e.what());
    return 1;
  }
}
