// One scene's sweep image: per pixel, at the surface point seen through the pixel centre, the
// escape counts of countEscapes, the bent normal from their first bounce, the true specular
// occlusion of traceSpecular, and the EXR channels derived from them (docs/sweep.md §1,
// docs/index.md "Pipeline").
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/image_io.h"
#include "sweep/escape_walk.h"
#include "sweep/specular_occlusion.h"
#include "sweep/sweep_set.h"

namespace gtbake {

// The albedos of the paper's sweep (Section 5) and their channel names G010 … G090.
inline constexpr double kSweepAlbedos[] = {0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 0.9};

// A half-open rectangle of pixels [x0, x1) × [y0, y1) of a width × height image.
struct PixelRect {
  int x0 = 0;
  int y0 = 0;
  int x1 = 0;
  int y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  std::size_t pixels() const {
    return static_cast<std::size_t>(width()) * static_cast<std::size_t>(height());
  }
};

struct EscapeImage {
  int width = 0;  // of the traced rectangle (the whole image unless a PixelRect was given)
  int height = 0;
  WalkSettings settings;
  std::vector<std::uint8_t> mask;     // 1 = the pixel's camera ray hit geometry
  std::vector<std::uint32_t> counts;  // per pixel 2(K+1): half h, bounce k at h(K+1) + k
  // Per pixel, world space, xyz at 3p: the normal n at the hit (geometric, facing the camera),
  // ωo (unit, from the hit to the camera) and the bent normal b (n if no first bounce escaped).
  std::vector<float> normal;
  std::vector<float> view;
  std::vector<float> bent;
  // Per pixel: linear view depth Z (metres along the camera's forward axis −basis.col(2) from the
  // camera to the hit) and, per G-buffer radius r (settings.gbuffer_radii), the near-field escape
  // counts (countEscapes' near_counts) at (p·radii + r)·2(K+1) + h(K+1) + k.
  std::vector<float> depth;
  std::vector<std::uint32_t> near_counts;
  // Per pixel and roughness j (R = settings.specular_roughness.size()): Ŝ, H0, H1 at
  // 3(pR + j) + {0, 1, 2}; near-field Ŝ_R, H0, H1 per radius r at 3((p·radii + r)R + j) + ….
  std::vector<float> specular;
  std::vector<float> specular_near;
  // Per pixel, with settings.transfer (else empty): T_{k,i} = Σ Y_i(escape direction) / N over the
  // walks that escape after exactly k bounces, at p·9(K+1) + 9k + i (docs/sweep.md, "Transfer").
  std::vector<float> transfer;
  std::uint64_t rays = 0;  // camera rays + walk segments + specular rays
  double seconds = 0.0;    // tracing wall time (BVH build excluded)

  std::uint64_t unmaskedPixels() const;
  // Escape count for pixel p, half h, bounce k.
  std::uint32_t count(std::size_t p, int h, int k) const {
    return counts[p * 2 * (settings.bounces + 1) + h * (settings.bounces + 1) + k];
  }
  // Near-field escape count at G-buffer radius index r.
  std::uint32_t nearCount(std::size_t p, std::size_t r, int h, int k) const {
    return near_counts[((p * settings.gbuffer_radii.size() + r) * 2 + h) * (settings.bounces + 1) +
                       k];
  }
};

// An image of width × height pixels with every array sized and zero (mask 0).
EscapeImage makeEscapeImage(int width, int height, const WalkSettings& settings);

// Per-thread buffers of tracePixel.
struct PixelScratch {
  WalkScratch walks;
  SpecularScratch specular;
  std::vector<double> sums;
  std::vector<double> near_sums;
  std::vector<double> transfer_sums;
};

// Everything the sweep records for pixel (i, j) of a width × height image, stored at `slot` of
// `image` (whose arrays makeEscapeImage sized): the camera ray, and on a hit the walks, the bent
// normal and the specular samples, all from the random stream pixelStream(settings.view_key,
// j·width + i). Returns the rays traced. A pixel's values depend only on (seed, scene, pixel), so
// any rectangle, thread count or shard gives the same bits.
std::uint64_t tracePixel(const EmbreeTracer& tracer, const PerspectiveCamera& camera, int width,
                         int height, int i, int j, std::size_t slot, EscapeImage* image,
                         PixelScratch* scratch);

// Traces the pixels of `rect` of a width × height image (TBB over 8×8 blocks, tracePixel); the
// result holds rect's pixels row-major.
EscapeImage traceEscapeImage(const EmbreeTracer& tracer, const PerspectiveCamera& camera, int width,
                             int height, const PixelRect& rect, const WalkSettings& settings,
                             const std::string& progress_label, bool progress);

// Every pixel of the image.
inline EscapeImage traceEscapeImage(const EmbreeTracer& tracer, const PerspectiveCamera& camera,
                                    int width, int height, const WalkSettings& settings,
                                    const std::string& progress_label, bool progress) {
  return traceEscapeImage(tracer, camera, width, height, PixelRect{0, 0, width, height}, settings,
                          progress_label, progress);
}

// EXR channels: A, P1..PK, G010 … G090, mask, NX NY NZ, VX VY VZ, BNX BNY BNZ, Z, A_R… (one per
// G-buffer radius, gbufferRadiusChannelName), S010 …, then
// H0.A, H0.P1..PK, H1.A, H1.P1..PK, H0.S010 …, H1.S010 …, then per G-buffer radius the rest of
// its near-field channels, the names with nearFieldChannelName's suffix: P1_R1..PK_R1,
// G010_R1 …, S010_R1 …, H0.A_R1, H0.P1_R1 …, H1.A_R1 …, H0.S010_R1 …, H1.S010_R1 … (masked = 0).
std::vector<ExrChannel> escapeChannels(const EscapeImage& image);

}  // namespace gtbake
