#include "sweep/escape_image.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "common/progress.h"
#include "common/spherical_harmonics.h"
#include "common/text_format.h"
#include "sweep/sweep_set.h"

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
  const std::size_t radii = settings.gbuffer_radii.size();
  image.near_counts.assign(pixels * radii * 2 * static_cast<std::size_t>(settings.bounces + 1), 0);
  image.specular.assign(3 * pixels * settings.specular_roughness.size(), 0.0f);
  image.specular_near.assign(3 * pixels * radii * settings.specular_roughness.size(), 0.0f);
  if (settings.transfer) {
    image.transfer.assign(pixels * kShCoefficients * static_cast<std::size_t>(settings.bounces + 1),
                          0.0f);
  }
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
      pixelStream(settings.view_key, static_cast<std::uint64_t>(j) * width + i);
  const std::size_t per_pixel = 2 * static_cast<std::size_t>(settings.bounces + 1);
  double bent[3] = {0.0, 0.0, 0.0};
  const std::size_t radii = settings.gbuffer_radii.size();
  const std::size_t transfer = settings.transfer ? per_pixel / 2 * kShCoefficients : 0;
  scratch->transfer_sums.assign(transfer, 0.0);
  std::uint64_t rays =
      1 + countEscapes(tracer, hit, settings, stream, &image->counts[p * per_pixel],
                       &scratch->walks, bent,
                       radii > 0 ? &image->near_counts[p * radii * per_pixel] : nullptr,
                       transfer > 0 ? scratch->transfer_sums.data() : nullptr);
  for (std::size_t c = 0; c < transfer; ++c) {
    image->transfer[p * transfer + c] =
        static_cast<float>(scratch->transfer_sums[c] / settings.spp);
  }
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
  scratch->near_sums.assign(2 * radii * roughness, 0.0);
  rays += traceSpecular(tracer, hit, wo, settings, stream, scratch->sums.data(), &scratch->specular,
                        radii > 0 ? scratch->near_sums.data() : nullptr);
  float* out = &image->specular[3 * p * roughness];
  float* near_out = radii > 0 ? &image->specular_near[3 * p * radii * roughness] : nullptr;
  for (std::size_t j = 0; j < roughness; ++j) {
    const double* sum = &scratch->sums[4 * j];
    out[3 * j] = static_cast<float>(specularRatio(sum[0] + sum[2], sum[1] + sum[3]));
    out[3 * j + 1] = static_cast<float>(specularRatio(sum[0], sum[1]));
    out[3 * j + 2] = static_cast<float>(specularRatio(sum[2], sum[3]));
    for (std::size_t r = 0; r < radii; ++r) {
      const double* near = &scratch->near_sums[2 * (r * roughness + j)];
      float* v = near_out + 3 * (r * roughness + j);
      v[0] = static_cast<float>(specularRatio(near[0] + near[1], sum[1] + sum[3]));
      v[1] = static_cast<float>(specularRatio(near[0], sum[1]));
      v[2] = static_cast<float>(specularRatio(near[1], sum[3]));
    }
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

ExrChannel blankChannel(const std::string& name, std::size_t pixels) {
  return ExrChannel{name, std::vector<float>(pixels, 0.0f)};
}

// The channels of one set of escape counts (the unbounded ones or one G-buffer radius's), named
// through `name`: A, P1..PK, G010 … and the halves H0.A, H0.P1 …, H1.…
struct EscapeChannels {
  std::vector<ExrChannel> full;  // A, P1..PK
  std::vector<ExrChannel> halves[2];
  std::vector<ExrChannel> g;
};

// count(p, h, k): the walks of half h of pixel p that escape after exactly k bounces.
template <class Count, class Name>
EscapeChannels escapeCountChannels(const EscapeImage& image, const Count& count, const Name& name) {
  const int bounces = image.settings.bounces;
  const std::size_t pixels = image.mask.size();
  const double n_full = image.settings.spp;
  const double n_half = 0.5 * n_full;
  auto pName = [](int k) { return k == 0 ? std::string("A") : "P" + std::to_string(k); };
  EscapeChannels c;
  for (int k = 0; k <= bounces; ++k) {
    c.full.push_back(blankChannel(name(pName(k)), pixels));
    for (int h = 0; h < 2; ++h)
      c.halves[h].push_back(blankChannel("H" + std::to_string(h) + "." + name(pName(k)), pixels));
  }
  for (double albedo : kSweepAlbedos)
    c.g.push_back(blankChannel(name(albedoChannelName(albedo)), pixels));
  for (std::size_t p = 0; p < pixels; ++p) {
    if (image.mask[p] == 0) continue;
    for (int k = 0; k <= bounces; ++k) {
      const std::uint32_t c0 = count(p, 0, k);
      const std::uint32_t c1 = count(p, 1, k);
      c.full[k].pixels[p] = static_cast<float>((static_cast<double>(c0) + c1) / n_full);
      c.halves[0][k].pixels[p] = static_cast<float>(c0 / n_half);
      c.halves[1][k].pixels[p] = static_cast<float>(c1 / n_half);
    }
    for (std::size_t a = 0; a < c.g.size(); ++a) {
      // Ĝ(ρ) = Σ_k ρ^k c_k / N, Horner order in double.
      double sum = 0.0;
      for (int k = bounces; k >= 0; --k) {
        sum = sum * kSweepAlbedos[a] +
              (static_cast<double>(count(p, 0, k)) + count(p, 1, k)) / n_full;
      }
      c.g[a].pixels[p] = static_cast<float>(sum);
    }
  }
  return c;
}

// The S channels of one set of specular values (values[3(p·stride + offset + j) + {0, 1, 2}] =
// Ŝ, H0, H1 of roughness j), named through `name`: S010 … and the halves H0.S010 …, H1.S010 …
template <class Name>
std::vector<ExrChannel> specularChannels(const EscapeImage& image, const std::vector<float>& values,
                                         std::size_t stride, std::size_t offset, const Name& name,
                                         std::vector<ExrChannel> halves[2]) {
  const std::size_t pixels = image.mask.size();
  std::vector<ExrChannel> full;
  for (double r : image.settings.specular_roughness) {
    full.push_back(blankChannel(name(specularChannelName(r)), pixels));
    for (int h = 0; h < 2; ++h) {
      halves[h].push_back(
          blankChannel("H" + std::to_string(h) + "." + name(specularChannelName(r)), pixels));
    }
  }
  for (std::size_t p = 0; p < pixels; ++p) {
    if (image.mask[p] == 0) continue;
    for (std::size_t j = 0; j < full.size(); ++j) {
      const float* s = &values[3 * (p * stride + offset + j)];
      full[j].pixels[p] = s[0];
      halves[0][j].pixels[p] = s[1];
      halves[1][j].pixels[p] = s[2];
    }
  }
  return full;
}

void appendChannels(std::vector<ExrChannel>* to, std::vector<ExrChannel>&& from) {
  for (auto& c : from) to->push_back(std::move(c));
}

// Every near-field channel of G-buffer radius index r (docs/sweep.md, "Near-field truth"): A_R
// first, then the order of escapeChannels' comment.
std::vector<ExrChannel> nearFieldChannels(const EscapeImage& image, std::size_t r) {
  const double radius = image.settings.gbuffer_radii[r];
  const auto name = [radius](const std::string& base) {
    return nearFieldChannelName(base, radius);
  };
  const auto count = [&image, r](std::size_t p, int h, int k) {
    return image.nearCount(p, r, h, k);
  };
  EscapeChannels escape = escapeCountChannels(image, count, name);
  std::vector<ExrChannel> specular_halves[2];
  const std::size_t roughness = image.settings.specular_roughness.size();
  std::vector<ExrChannel> specular =
      specularChannels(image, image.specular_near, image.settings.gbuffer_radii.size() * roughness,
                       r * roughness, name, specular_halves);
  std::vector<ExrChannel> channels = std::move(escape.full);
  appendChannels(&channels, std::move(escape.g));
  appendChannels(&channels, std::move(specular));
  for (auto& half : escape.halves) appendChannels(&channels, std::move(half));
  for (auto& half : specular_halves) appendChannels(&channels, std::move(half));
  return channels;
}

// T0_SH0 … TK_SH8 with settings.transfer, else none.
std::vector<ExrChannel> transferChannels(const EscapeImage& image) {
  std::vector<ExrChannel> channels;
  if (!image.settings.transfer) return channels;
  const std::size_t pixels = image.mask.size();
  const std::size_t per_pixel =
      kShCoefficients * static_cast<std::size_t>(image.settings.bounces + 1);
  for (int k = 0; k <= image.settings.bounces; ++k) {
    for (int i = 0; i < kShCoefficients; ++i) {
      ExrChannel c = blankChannel(transferChannelName(k, i), pixels);
      for (std::size_t p = 0; p < pixels; ++p)
        c.pixels[p] = image.transfer[p * per_pixel + kShCoefficients * k + i];
      channels.push_back(std::move(c));
    }
  }
  return channels;
}

}  // namespace

std::vector<ExrChannel> escapeChannels(const EscapeImage& image) {
  const std::size_t pixels = image.mask.size();
  const auto same = [](const std::string& base) { return base; };
  const auto count = [&image](std::size_t p, int h, int k) { return image.count(p, h, k); };
  EscapeChannels escape = escapeCountChannels(image, count, same);
  ExrChannel mask = blankChannel("mask", pixels);
  // NX NY NZ, VX VY VZ, BNX BNY BNZ.
  std::vector<ExrChannel> vectors;
  const std::vector<float>* sources[3] = {&image.normal, &image.view, &image.bent};
  for (const char* prefix : {"N", "V", "BN"}) {
    for (const char* axis : {"X", "Y", "Z"})
      vectors.push_back(blankChannel(std::string(prefix) + axis, pixels));
  }
  for (std::size_t p = 0; p < pixels; ++p) {
    if (image.mask[p] == 0) continue;
    mask.pixels[p] = 1.0f;
    for (int v = 0; v < 3; ++v) {
      for (int c = 0; c < 3; ++c) vectors[3 * v + c].pixels[p] = (*sources[v])[3 * p + c];
    }
  }
  std::vector<ExrChannel> specular_halves[2];
  std::vector<ExrChannel> specular = specularChannels(
      image, image.specular, image.settings.specular_roughness.size(), 0, same, specular_halves);
  // Per G-buffer radius, A_R (with Z, the G-buffer channels) and the rest.
  std::vector<std::vector<ExrChannel>> near;
  std::vector<ExrChannel> gbuffer = {{"Z", image.depth}};
  for (std::size_t r = 0; r < image.settings.gbuffer_radii.size(); ++r) {
    near.push_back(nearFieldChannels(image, r));
    gbuffer.push_back(std::move(near.back().front()));
    near.back().erase(near.back().begin());
  }

  std::vector<ExrChannel> channels = std::move(escape.full);
  appendChannels(&channels, std::move(escape.g));
  channels.push_back(std::move(mask));
  appendChannels(&channels, std::move(vectors));
  appendChannels(&channels, std::move(gbuffer));
  appendChannels(&channels, std::move(specular));
  for (auto& half : escape.halves) appendChannels(&channels, std::move(half));
  for (auto& half : specular_halves) appendChannels(&channels, std::move(half));
  for (auto& radius : near) appendChannels(&channels, std::move(radius));
  appendChannels(&channels, transferChannels(image));
  return channels;
}

}  // namespace gtbake
