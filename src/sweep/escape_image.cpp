#include "sweep/escape_image.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "common/progress.h"
#include "common/text_format.h"

namespace gtbake {

namespace {

constexpr int kTileSize = 8;  // pixels: 64 pixels × spp walks per task is far above TBB's overhead,
                              // and ≥ 64 tiles at 64×64 px keep 2 threads balanced

}  // namespace

std::uint64_t EscapeImage::unmaskedPixels() const {
  return static_cast<std::uint64_t>(std::count(mask.begin(), mask.end(), std::uint8_t{1}));
}

EscapeImage makeEscapeImage(int width, int height, const WalkSettings& settings) {
  EscapeImage image;
  image.width = width;
  image.height = height;
  image.settings = settings;
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  image.mask.assign(pixels, 0);
  image.counts.assign(pixels * 2 * static_cast<std::size_t>(settings.bounces + 1), 0);
  image.normal.assign(3 * pixels, 0.0f);
  image.view.assign(3 * pixels, 0.0f);
  image.bent.assign(3 * pixels, 0.0f);
  image.depth.assign(pixels, 0.0f);
  image.radius_hits.assign(pixels * settings.gbuffer_radii.size(), 0);
  image.specular.assign(3 * pixels * settings.specular_roughness.size(), 0.0f);
  return image;
}

std::uint64_t tracePixel(const EmbreeTracer& tracer, const PerspectiveCamera& camera, int width,
                         int height, int i, int j, std::size_t slot, EscapeImage* image,
                         PixelScratch* scratch) {
  const WalkSettings& settings = image->settings;
  const std::size_t p = slot;
  const Ray camera_ray = cameraRay(camera, i, j, width, height);
  SurfaceHit hit;
  if (!tracer.intersect(camera_ray, INFINITY, &hit)) return 1;
  image->mask[p] = 1;
  const std::uint64_t stream =
      pixelStream(settings.scene_key, static_cast<std::uint64_t>(j) * width + i);
  const std::size_t per_pixel = 2 * static_cast<std::size_t>(settings.bounces + 1);
  double bent[3] = {0.0, 0.0, 0.0};
  const std::size_t radii = settings.gbuffer_radii.size();
  std::uint64_t rays =
      1 + countEscapes(tracer, hit, settings, stream, &image->counts[p * per_pixel],
                       &scratch->walks, bent, radii > 0 ? &image->radius_hits[p * radii] : nullptr);
  const Eigen::Vector3d forward = -camera.basis.col(2);
  image->depth[p] =
      static_cast<float>((hit.position.cast<double>() - camera.position).dot(forward));
  const float wo[3] = {-camera_ray.direction.x(), -camera_ray.direction.y(),
                       -camera_ray.direction.z()};
  const double length = std::sqrt(bent[0] * bent[0] + bent[1] * bent[1] + bent[2] * bent[2]);
  for (int c = 0; c < 3; ++c) {
    image->normal[3 * p + c] = hit.normal[c];
    image->view[3 * p + c] = wo[c];
    image->bent[3 * p + c] = length > 0.0 ? static_cast<float>(bent[c] / length) : hit.normal[c];
  }
  const std::size_t roughness = settings.specular_roughness.size();
  if (roughness == 0) return rays;
  scratch->sums.assign(4 * roughness, 0.0);
  rays +=
      traceSpecular(tracer, hit, wo, settings, stream, scratch->sums.data(), &scratch->specular);
  float* out = &image->specular[3 * p * roughness];
  for (std::size_t r = 0; r < roughness; ++r) {
    const double* sum = &scratch->sums[4 * r];
    out[3 * r] = static_cast<float>(specularRatio(sum[0] + sum[2], sum[1] + sum[3]));
    out[3 * r + 1] = static_cast<float>(specularRatio(sum[0], sum[1]));
    out[3 * r + 2] = static_cast<float>(specularRatio(sum[2], sum[3]));
  }
  return rays;
}

EscapeImage traceEscapeImage(const EmbreeTracer& tracer, const PerspectiveCamera& camera, int width,
                             int height, const PixelRect& rect, const WalkSettings& settings,
                             const std::string& progress_label, bool progress) {
  EscapeImage image = makeEscapeImage(rect.width(), rect.height(), settings);
  const int tiles_x = (rect.width() + kTileSize - 1) / kTileSize;
  const int tiles_y = (rect.height() + kTileSize - 1) / kTileSize;
  Progress bar(progress_label, rect.pixels(), progress);
  std::atomic<std::uint64_t> rays{0};
  const auto start = std::chrono::steady_clock::now();
  tbb::parallel_for(
      tbb::blocked_range<int>(0, tiles_x * tiles_y, 1), [&](const tbb::blocked_range<int>& range) {
        for (int tile = range.begin(); tile != range.end(); ++tile) {
          const int x0 = rect.x0 + (tile % tiles_x) * kTileSize;
          const int y0 = rect.y0 + (tile / tiles_x) * kTileSize;
          const int x1 = std::min(x0 + kTileSize, rect.x1);
          const int y1 = std::min(y0 + kTileSize, rect.y1);
          std::uint64_t tile_rays = 0;
          PixelScratch scratch;
          for (int j = y0; j < y1; ++j) {
            for (int i = x0; i < x1; ++i) {
              const std::size_t slot = static_cast<std::size_t>(j - rect.y0) * rect.width() +
                                       static_cast<std::size_t>(i - rect.x0);
              tile_rays += tracePixel(tracer, camera, width, height, i, j, slot, &image, &scratch);
            }
          }
          rays += tile_rays;
          bar.add(static_cast<std::uint64_t>(x1 - x0) * (y1 - y0));
        }
      });
  bar.finish();
  image.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  image.rays = rays.load();
  return image;
}

namespace {

// `prefix` and the value in hundredths, three digits ("G050" for 0.5).
std::string hundredthsChannelName(char prefix, double value) {
  return prefix + formatNumber(std::round(value * 100.0), "%03.0f");
}

}  // namespace

std::string albedoChannelName(double albedo) {
  return hundredthsChannelName('G', albedo);
}

std::string gbufferRadiusChannelName(double radius) {
  std::string name = "A_R" + formatNumber(radius, "%g");
  std::replace(name.begin(), name.end(), '.', 'p');
  return name;
}

std::string specularChannelName(double roughness) {
  return hundredthsChannelName('S', roughness);
}

namespace {

// Z, then A_R per G-buffer radius: (c_0 + first hits beyond R)/N (docs/sweep.md, "G-buffer").
std::vector<ExrChannel> gbufferChannels(const EscapeImage& image) {
  const std::size_t pixels = image.mask.size();
  const std::size_t radii = image.settings.gbuffer_radii.size();
  std::vector<ExrChannel> channels = {{"Z", image.depth}};
  for (float r : image.settings.gbuffer_radii) {
    channels.push_back({gbufferRadiusChannelName(r), std::vector<float>(pixels, 0.0f)});
  }
  for (std::size_t p = 0; p < pixels; ++p) {
    if (image.mask[p] == 0) continue;
    const double escaped = static_cast<double>(image.count(p, 0, 0)) + image.count(p, 1, 0);
    for (std::size_t r = 0; r < radii; ++r) {
      channels[1 + r].pixels[p] = static_cast<float>((escaped + image.radius_hits[p * radii + r]) /
                                                     static_cast<double>(image.settings.spp));
    }
  }
  return channels;
}

}  // namespace

std::vector<ExrChannel> escapeChannels(const EscapeImage& image) {
  const int bounces = image.settings.bounces;
  const std::size_t pixels = image.mask.size();
  const double n_full = image.settings.spp;
  const double n_half = 0.5 * n_full;
  auto blank = [&](const std::string& name) {
    return ExrChannel{name, std::vector<float>(pixels, 0.0f)};
  };
  auto pName = [](int k) { return k == 0 ? std::string("A") : "P" + std::to_string(k); };

  std::vector<ExrChannel> full;  // A, P1..PK
  std::vector<ExrChannel> halves[2];
  for (int k = 0; k <= bounces; ++k) {
    full.push_back(blank(pName(k)));
    for (int h = 0; h < 2; ++h)
      halves[h].push_back(blank("H" + std::to_string(h) + "." + pName(k)));
  }
  std::vector<ExrChannel> g;
  for (double albedo : kSweepAlbedos) g.push_back(blank(albedoChannelName(albedo)));
  ExrChannel mask = blank("mask");
  // NX NY NZ, VX VY VZ, BNX BNY BNZ.
  std::vector<ExrChannel> vectors;
  const std::vector<float>* sources[3] = {&image.normal, &image.view, &image.bent};
  for (const char* prefix : {"N", "V", "BN"}) {
    for (const char* axis : {"X", "Y", "Z"}) vectors.push_back(blank(std::string(prefix) + axis));
  }
  const std::size_t roughness = image.settings.specular_roughness.size();
  std::vector<ExrChannel> specular;
  std::vector<ExrChannel> specular_halves[2];
  for (double r : image.settings.specular_roughness) {
    specular.push_back(blank(specularChannelName(r)));
    for (int h = 0; h < 2; ++h) {
      specular_halves[h].push_back(blank("H" + std::to_string(h) + "." + specularChannelName(r)));
    }
  }

  for (std::size_t p = 0; p < pixels; ++p) {
    if (image.mask[p] == 0) continue;
    mask.pixels[p] = 1.0f;
    for (int k = 0; k <= bounces; ++k) {
      const std::uint32_t c0 = image.count(p, 0, k);
      const std::uint32_t c1 = image.count(p, 1, k);
      full[k].pixels[p] = static_cast<float>((static_cast<double>(c0) + c1) / n_full);
      halves[0][k].pixels[p] = static_cast<float>(c0 / n_half);
      halves[1][k].pixels[p] = static_cast<float>(c1 / n_half);
    }
    for (std::size_t a = 0; a < g.size(); ++a) {
      // Ĝ(ρ) = Σ_k ρ^k c_k / N, Horner order in double.
      double sum = 0.0;
      for (int k = bounces; k >= 0; --k) {
        sum = sum * kSweepAlbedos[a] +
              (static_cast<double>(image.count(p, 0, k)) + image.count(p, 1, k)) / n_full;
      }
      g[a].pixels[p] = static_cast<float>(sum);
    }
    for (int v = 0; v < 3; ++v) {
      for (int c = 0; c < 3; ++c) vectors[3 * v + c].pixels[p] = (*sources[v])[3 * p + c];
    }
    for (std::size_t r = 0; r < roughness; ++r) {
      const float* s = &image.specular[3 * (p * roughness + r)];
      specular[r].pixels[p] = s[0];
      specular_halves[0][r].pixels[p] = s[1];
      specular_halves[1][r].pixels[p] = s[2];
    }
  }

  std::vector<ExrChannel> channels = std::move(full);
  for (auto& c : g) channels.push_back(std::move(c));
  channels.push_back(std::move(mask));
  for (auto& c : vectors) channels.push_back(std::move(c));
  for (auto& c : gbufferChannels(image)) channels.push_back(std::move(c));
  for (auto& c : specular) channels.push_back(std::move(c));
  for (auto& half : halves) {
    for (auto& c : half) channels.push_back(std::move(c));
  }
  for (auto& half : specular_halves) {
    for (auto& c : half) channels.push_back(std::move(c));
  }
  return channels;
}

}  // namespace gtbake
