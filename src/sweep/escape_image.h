// One scene's sweep image: per pixel, the escape counts of countEscapes at the surface point seen
// through the pixel centre, and the EXR channels derived from them (SPEC §1.1, §2).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/image_io.h"
#include "sweep/escape_walk.h"

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
  std::uint64_t rays = 0;             // camera rays + walk segments
  double seconds = 0.0;               // tracing wall time (BVH build excluded)

  std::uint64_t unmaskedPixels() const;
  // Escape count for pixel p, half h, bounce k.
  std::uint32_t count(std::size_t p, int h, int k) const {
    return counts[p * 2 * (settings.bounces + 1) + h * (settings.bounces + 1) + k];
  }
};

// Traces the pixels of `rect` of a width × height image (TBB over 8×8 blocks); the result holds
// rect's pixels row-major. Each pixel (i, j) uses the random stream of its index j·width + i in
// the whole image, so its values are the same for any thread count and whichever rectangle
// contains it.
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

// EXR channels: A, P1..PK, G010 … G090, mask, H0.A, H0.P1..PK, H1.A, H1.P1..PK (masked = 0).
std::vector<ExrChannel> escapeChannels(const EscapeImage& image);

// G(ρ) channel name, e.g. 0.5 -> "G050".
std::string albedoChannelName(double albedo);

}  // namespace gtbake
