#include "sweep/escape_image.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "common/progress.h"

namespace gtbake {

namespace {

constexpr int kTileSize = 8;  // pixels: 64 pixels × spp walks per task is far above TBB's overhead,
                              // and ≥ 64 tiles at 64×64 px keep 2 threads balanced

}  // namespace

std::uint64_t EscapeImage::unmaskedPixels() const {
  return static_cast<std::uint64_t>(std::count(mask.begin(), mask.end(), std::uint8_t{1}));
}

EscapeImage traceEscapeImage(const EmbreeTracer& tracer, const PerspectiveCamera& camera, int width,
                             int height, const PixelRect& rect, const WalkSettings& settings,
                             const std::string& progress_label, bool progress) {
  EscapeImage image;
  image.width = rect.width();
  image.height = rect.height();
  image.settings = settings;
  const std::size_t pixels = rect.pixels();
  const std::size_t per_pixel = 2 * static_cast<std::size_t>(settings.bounces + 1);
  image.mask.assign(pixels, 0);
  image.counts.assign(pixels * per_pixel, 0);

  const int tiles_x = (rect.width() + kTileSize - 1) / kTileSize;
  const int tiles_y = (rect.height() + kTileSize - 1) / kTileSize;
  Progress bar(progress_label, pixels, progress);
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
          WalkScratch scratch;
          for (int j = y0; j < y1; ++j) {
            for (int i = x0; i < x1; ++i) {
              const std::size_t p = static_cast<std::size_t>(j - rect.y0) * rect.width() +
                                    static_cast<std::size_t>(i - rect.x0);
              const std::uint64_t stream = static_cast<std::uint64_t>(j) * width + i;
              SurfaceHit hit;
              ++tile_rays;
              if (!tracer.intersect(cameraRay(camera, i, j, width, height), INFINITY, &hit)) {
                continue;
              }
              image.mask[p] = 1;
              tile_rays += countEscapes(tracer, hit, settings, stream, &image.counts[p * per_pixel],
                                        &scratch);
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

std::string albedoChannelName(double albedo) {
  char name[8];
  std::snprintf(name, sizeof(name), "G%03d", static_cast<int>(std::lround(albedo * 100.0)));
  return name;
}

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
  }

  std::vector<ExrChannel> channels = std::move(full);
  for (auto& c : g) channels.push_back(std::move(c));
  channels.push_back(std::move(mask));
  for (auto& half : halves) {
    for (auto& c : half) channels.push_back(std::move(c));
  }
  return channels;
}

}  // namespace gtbake
