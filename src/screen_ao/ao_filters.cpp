#include "screen_ao/ao_filters.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "screen_ao/pixel_loop.h"

namespace gtbake {

namespace {

constexpr int kBlurRadius = 2;      // 5×5
constexpr double kBlurSigma = 1.5;  // pixels
constexpr double kDepthRejection = 0.05;
constexpr std::size_t kTaps = (2 * kBlurRadius + 1) * (2 * kBlurRadius + 1);

bool inside(const GBuffer& g, int i, int j) {
  return i >= 0 && j >= 0 && i < g.width && j < g.height &&
         g.mask[static_cast<std::size_t>(j) * g.width + i] != 0;
}

// The depth edge weight between each pixel and its right (and lower) neighbour, 0 where that
// neighbour is off the image or masked: the blur's path products read these.
struct EdgeWeights {
  std::vector<double> right;
  std::vector<double> down;
};

EdgeWeights edgeWeights(const GBuffer& g) {
  EdgeWeights e{std::vector<double>(g.pixels(), 0.0), std::vector<double>(g.pixels(), 0.0)};
  for (int j = 0; j < g.height; ++j) {
    for (int i = 0; i < g.width; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * g.width + i;
      if (inside(g, i + 1, j)) e.right[p] = depthEdgeWeight(g.depth[p], g.depth[p + 1]);
      if (inside(g, i, j + 1)) e.down[p] = depthEdgeWeight(g.depth[p], g.depth[p + g.width]);
    }
  }
  return e;
}

// Product of the edge weights from (i, j) to (i + dx, j + dy): horizontal leg, then vertical.
double pathWeight(const GBuffer& g, const EdgeWeights& e, int i, int j, int dx, int dy) {
  double w = 1.0;
  const int sx = dx < 0 ? -1 : 1;
  const int sy = dy < 0 ? -1 : 1;
  int x = i;
  for (int k = 0; k < std::abs(dx); ++k, x += sx) {
    if (!inside(g, x + sx, j)) return 0.0;
    w *= e.right[static_cast<std::size_t>(j) * g.width + std::min(x, x + sx)];
  }
  int y = j;
  for (int k = 0; k < std::abs(dy); ++k, y += sy) {
    if (!inside(g, x, y + sy)) return 0.0;
    w *= e.down[static_cast<std::size_t>(std::min(y, y + sy)) * g.width + x];
  }
  return w;
}

Eigen::Vector3d decodeBent(const std::array<std::uint8_t, 4>& c) {
  return Eigen::Vector3d(c[0], c[1], c[2]) / 255.0 * 2.0 - Eigen::Vector3d::Ones();
}

// Pixel (i, j) reprojected: screen + depth -> world -> previous frame (the same static camera) ->
// previous pixel; −1 off-screen (layer 1), masked or more than 5 % off in depth (layer 2).
std::ptrdiff_t historyPixel(const GBuffer& g, int i, int j, std::size_t p) {
  const Eigen::Vector3d view = g.viewPoint(i, j, g.depth[p]);
  const Eigen::Vector3d world = g.camera.position + g.viewToWorld(view);
  const Eigen::Vector3d previous = g.worldToView(world - g.camera.position);
  const Eigen::Vector2d uv = g.project(previous);
  const int pi = static_cast<int>(std::floor(uv.x()));
  const int pj = static_cast<int>(std::floor(uv.y()));
  if (pi < 0 || pj < 0 || pi >= g.width || pj >= g.height) return -1;  // layer 1
  const std::size_t q = static_cast<std::size_t>(pj) * g.width + pi;
  const double expected = -previous.z();
  if (g.mask[q] == 0 || !(std::abs(expected - g.depth[q]) / expected <= kDepthRejection)) {
    return -1;  // layer 2
  }
  return static_cast<std::ptrdiff_t>(q);
}

}  // namespace

double depthEdgeWeight(double z1, double z2) {
  return std::clamp(1.0 - std::abs(z1 - z2) / (std::max(z1, z2) * 0.05), 0.0, 1.0);
}

FilterSetup filterSetup(const GBuffer& g) {
  double gauss[2 * kBlurRadius + 1][2 * kBlurRadius + 1];  // the spatial weights, once
  for (int dy = -kBlurRadius; dy <= kBlurRadius; ++dy) {
    for (int dx = -kBlurRadius; dx <= kBlurRadius; ++dx) {
      gauss[dy + kBlurRadius][dx + kBlurRadius] =
          std::exp(-(dx * dx + dy * dy) / (2.0 * kBlurSigma * kBlurSigma));
    }
  }
  const EdgeWeights edges = edgeWeights(g);
  FilterSetup f{std::vector<double>(kTaps * g.pixels(), 0.0),
                std::vector<std::ptrdiff_t>(g.pixels(), -1),
                std::vector<std::uint16_t>(g.pixels(), 0)};
  forEachMaskedPixel(g, [&](int i, int j, std::size_t p) {
    double* w = &f.blur[kTaps * p];
    for (int dy = -kBlurRadius; dy <= kBlurRadius; ++dy) {
      for (int dx = -kBlurRadius; dx <= kBlurRadius; ++dx) {
        *w++ = gauss[dy + kBlurRadius][dx + kBlurRadius] * pathWeight(g, edges, i, j, dx, dy);
      }
    }
    f.history[p] = historyPixel(g, i, j, p);
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (inside(g, i + dx, j + dy)) f.around[p] |= 1u << (3 * (dy + 1) + dx + 1);
      }
    }
  });
  return f;
}

namespace {

// The blur of channels First…3 at pixel (i, j) into out (bilateralBlur's; First a constant so
// the channel loop unrolls).
template <int First>
void blurPixel(const GBuffer& g, const FilterSetup& f, const Rgba8Image& in, int i, int j,
               std::size_t p, Rgba8Image* out) {
  const double* w = &f.blur[kTaps * p];
  double sum[4] = {0.0, 0.0, 0.0, 0.0};
  double total = 0.0;
  for (int dy = -kBlurRadius; dy <= kBlurRadius; ++dy) {
    const auto* row = &in[static_cast<std::size_t>(j + dy) * g.width + i];
    for (int dx = -kBlurRadius; dx <= kBlurRadius; ++dx, ++w) {
      if (!(*w > 0.0)) continue;
      const auto& c = row[dx];
      for (int k = First; k < 4; ++k) sum[k] += *w * c[k] / 255.0;
      total += *w;
    }
  }
  for (int k = First; k < 4; ++k) (*out)[p][k] = unorm8(sum[k] / total);
}

}  // namespace

Rgba8Image bilateralBlur(const GBuffer& g, const FilterSetup& f, const Rgba8Image& in,
                         EstimateParts parts) {
  Rgba8Image out(in.size(), {0, 0, 0, 0});
  if (parts == EstimateParts::kAoOnly) {  // A alone
    forEachMaskedPixel(g,
                       [&](int i, int j, std::size_t p) { blurPixel<3>(g, f, in, i, j, p, &out); });
  } else {
    forEachMaskedPixel(g,
                       [&](int i, int j, std::size_t p) { blurPixel<0>(g, f, in, i, j, p, &out); });
  }
  return out;
}

Rgba8Image temporalFilter(const GBuffer& g, const FilterSetup& f, const Rgba8Image& current,
                          const Rgba8Image& history, double blend, EstimateParts parts) {
  if (history.empty() || blend == 0.0) return current;
  Rgba8Image out(current.size(), {0, 0, 0, 0});
  forEachMaskedPixel(g, [&](int i, int j, std::size_t p) {
    const auto& c = current[p];
    if (f.history[p] < 0) {
      out[p] = c;
      return;
    }
    const auto q = static_cast<std::size_t>(f.history[p]);
    // The 3×3 extremes of the bytes, divided once: a/255 rises with a, so the extreme of the
    // quotients is the quotient of the extreme byte (the centre is inside, and every a/255 lies
    // in [0, 1], the fold's start values).
    std::uint8_t lo_byte = 255;
    std::uint8_t hi_byte = 0;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if ((f.around[p] & (1u << (3 * (dy + 1) + dx + 1))) == 0) continue;
        const std::uint8_t a = current[static_cast<std::size_t>(j + dy) * g.width + (i + dx)][3];
        lo_byte = std::min(lo_byte, a);
        hi_byte = std::max(hi_byte, a);
      }
    }
    const double lo = lo_byte / 255.0;
    const double hi = hi_byte / 255.0;
    const double h_ao = std::clamp(history[q][3] / 255.0, lo, hi);  // layer 3
    const double c_ao = c[3] / 255.0;
    if (parts == EstimateParts::kAoOnly) {
      out[p] = {0, 0, 0, unorm8(c_ao + blend * (h_ao - c_ao))};
      return;
    }
    const Eigen::Vector3d cb = decodeBent(c);
    Eigen::Vector3d b = cb + blend * (decodeBent(history[q]) - cb);
    b = b.norm() > 1e-12 ? b.normalized() : cb;
    out[p] = {unorm8(b.x() * 0.5 + 0.5), unorm8(b.y() * 0.5 + 0.5), unorm8(b.z() * 0.5 + 0.5),
              unorm8(c_ao + blend * (h_ao - c_ao))};
  });
  return out;
}

AoEstimate decodeRgba8(const GBuffer& g, const Rgba8Image& image, EstimateParts parts) {
  AoEstimate e = makeEstimate(g, parts);
  for (std::size_t p = 0; p < g.pixels(); ++p) {
    if (g.mask[p] == 0) continue;
    e.a[p] = static_cast<float>(image[p][3] / 255.0);
    if (parts == EstimateParts::kAoOnly) continue;
    Eigen::Vector3d w = g.viewToWorld(decodeBent(image[p]));
    if (!(w.norm() > 1e-12))
      w = Eigen::Vector3d(g.normal[3 * p], g.normal[3 * p + 1], g.normal[3 * p + 2]);
    w.normalize();
    for (int c = 0; c < 3; ++c) e.bent[3 * p + c] = static_cast<float>(w[c]);
  }
  return e;
}

}  // namespace gtbake
