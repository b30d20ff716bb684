#include "screen_ao/gtao_runtime.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "common/error.h"
#include "screen_ao/ao_filters.h"
#include "screen_ao/pixel_loop.h"
#include "screen_ao/sample_image.h"
#include "screen_ao/slice_geometry.h"

namespace gtbake {

namespace {

double fract(double x) {
  return x - std::floor(x);
}

constexpr int kMaxDirections = 64;  // validate's bounds
constexpr int kMaxSteps = 256;
constexpr std::size_t kMaxThins = 8;  // thin compensations sharing one group's samples

// The quadratic steps' pixel offsets t_k = ((k + noise)/steps)² × R in pixels, at least the next
// texel; the same for every slice and side of a pixel's frame.
void stepOffsets(int steps, double step_noise, double radius_px, double* offsets) {
  for (int k = 0; k < steps; ++k) {
    const double linear = (k + step_noise) / steps;
    offsets[k] = std::max(1.0, linear * linear * radius_px);
  }
}

// The falloff of radius R: flat up to `from`, then linear over `range` (computed once per radius).
struct Falloff {
  double from, range;
};

Falloff falloffOf(double radius) {
  return {radius * (1.0 - kFalloffRange), kFalloffRange * radius};
}

// Flat inside R(1 − 0.615), then linear to 0 at R. The ends skip the division with its result: a
// quotient ≤ 0 clamps to 1, and a numerator ≥ the range makes it ≥ 1, which clamps to 0.
double falloffWeight(double distance, const Falloff& f) {
  const double over = distance - f.from;
  if (over <= 0.0) return 1.0;
  if (over >= f.range) return 0.0;
  return std::clamp(1.0 - over / f.range, 0.0, 1.0);
}

// One side's horizon cosine for each thin compensation of `thins`, into horizon_cos[t]: the samples
// at `offsets` (stepOffsets), each sample's cos blended towards the tangent plane's (low) horizon
// by the falloff weight, the falloff distance taken with the view-z part of the offset stretched by
// 1 + thin_compensation. The samples are shared; each value's maximum is the one a run at that
// value alone computes.
void sideHorizonCos(const SampleImage& image, int i, int j, const Eigen::Vector3d& x,
                    const Eigen::Vector3d& v, const Eigen::Vector2d& omega, double sign,
                    double low_cos, const double* offsets, int steps, const Falloff& falloff,
                    const std::vector<double>& thins, double* horizon_cos) {
  for (std::size_t t = 0; t < thins.size(); ++t) horizon_cos[t] = low_cos;
  for (int k = 0; k < steps; ++k) {
    const double offset = offsets[k];
    Eigen::Vector3d sample;
    if (!image.point(i + 0.5 + sign * offset * omega.x(), j + 0.5 - sign * offset * omega.y(),
                     &sample)) {
      continue;
    }
    const Eigen::Vector3d d = sample - x;
    const double length = d.norm();
    if (!(length > 0.0)) continue;
    const double sample_cos = d.dot(v) / length;
    // A sample no higher than the tangent plane blends to at most low_cos (the weight is in
    // [0, 1]), which never raises a maximum.
    if (sample_cos <= low_cos) continue;
    for (std::size_t t = 0; t < thins.size(); ++t) {
      // Without thin compensation the stretched offset is d itself (z·1 is exact).
      const double stretched =
          thins[t] == 0.0 ? length : Eigen::Vector3d(d.x(), d.y(), d.z() * (1.0 + thins[t])).norm();
      const double weight = falloffWeight(stretched, falloff);
      // At weight 0 the blend is low_cos, which never raises the running maximum.
      if (!(weight > 0.0)) continue;
      horizon_cos[t] = std::max(horizon_cos[t], low_cos + (sample_cos - low_cos) * weight);
    }
  }
}

// What a pixel's pass reads that neither the frame nor the run changes: P, V, the normal through
// the R10G10B10A2 buffer in view space, and its interleaved gradient noise.
// P's image point and the offset 10⁻³|P| are sliceAlong's, per pixel rather than per slice.
struct PixelSetup {
  Eigen::Vector3d x, v, normal;
  Eigen::Vector2d from;
  double offset = 0.0;
  double ign = 0.0;
};

std::vector<PixelSetup> pixelSetup(const GBuffer& g) {
  std::vector<PixelSetup> out(g.pixels());
  forEachMaskedPixel(g, [&](int i, int j, std::size_t p) {
    PixelSetup& px = out[p];
    px.x = viewPosition(g, p);
    px.v = -px.x.normalized();
    const Eigen::Vector3d world(g.normal[3 * p], g.normal[3 * p + 1], g.normal[3 * p + 2]);
    px.normal = g.worldToView(r10g10b10Normal(world));
    px.from = g.project(px.x);
    px.offset = 1e-3 * px.x.norm();
    px.ign = interleavedGradientNoise(i, j);
  });
  return out;
}

// Runs whose samples are the same: equal radius and steps. Each distinct thin compensation of them
// has its own horizons (thins[t]), shared by its runs (runs[t]: intensity only raises their sum to
// a power); a ninth thin compensation starts another group of the same radius.
struct HorizonGroup {
  double radius = 0.0;
  int steps = 0;
  std::vector<double> thins;
  std::vector<std::vector<std::size_t>> runs;
};

std::vector<HorizonGroup> horizonGroups(const std::vector<GtaoRuntimeSettings>& runs) {
  std::vector<HorizonGroup> groups;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const GtaoRuntimeSettings& s = runs[r];
    auto it = std::find_if(groups.begin(), groups.end(), [&](const HorizonGroup& h) {
      return h.radius == s.radius && h.steps == s.steps &&
             (h.thins.size() < kMaxThins ||
              std::find(h.thins.begin(), h.thins.end(), s.thin_compensation) != h.thins.end());
    });
    if (it == groups.end())
      it = groups.insert(groups.end(), HorizonGroup{s.radius, s.steps, {}, {}});
    const auto t = std::find(it->thins.begin(), it->thins.end(), s.thin_compensation);
    if (t == it->thins.end()) {
      it->thins.push_back(s.thin_compensation);
      it->runs.push_back({r});
    } else {
      it->runs[static_cast<std::size_t>(t - it->thins.begin())].push_back(r);
    }
  }
  return groups;
}

// A frame's slice at a pixel with its angle n computed the first time a horizon may clamp
// (horizonUnclamped): elsewhere horizonOf's value needs no n, so no atan2.
// Each side also keeps the last horizon computed, which a group or thin compensation with the same
// cos (often the plane's, low_cos, where no sample is in reach) takes as it is.
struct FrameSlice {
  Slice slice;
  bool angled = false;
  std::array<double, 2> last_cos;  // NaN before the first: equal to no cos
  std::array<Angle, 2> last;
};

// horizonOf(horizon_cos, side, slice) of the slice with its angle.
Angle sideHorizon(double horizon_cos, int side, FrameSlice* s) {
  if (horizon_cos == s->last_cos[side]) return s->last[side];
  const double floor_cos = side == 0 ? s->slice.sin_n : -s->slice.sin_n;  // cos(n ∓ π/2)
  s->last_cos[side] = horizon_cos;
  if (horizonUnclamped(horizon_cos, floor_cos, s->slice)) {
    s->last[side] = unclampedHorizon(horizon_cos, side);
  } else {
    if (!s->angled) {
      s->slice = withAngle(s->slice);
      s->angled = true;
    }
    s->last[side] = horizonOf(horizon_cos, side, s->slice);
  }
  return s->last[side];
}

// One group's horizons at pixel p for every thin compensation of it: visibility[t] and, unless
// sum is null, the unnormalised view-space bent normal sum[t].
void groupHorizons(const GBuffer& g, const SampleImage& image, int i, int j, std::size_t p,
                   const PixelSetup& px, FrameSlice* slices, int directions, double step_noise,
                   const HorizonGroup& group, double* visibility, Eigen::Vector3d* sum) {
  const std::size_t thins = group.thins.size();
  const Falloff falloff = falloffOf(group.radius);
  std::array<double, kMaxSteps> offsets;
  stepOffsets(group.steps, step_noise, group.radius * g.pixelsPerMetre(g.depth[p]), offsets.data());
  for (std::size_t t = 0; t < thins; ++t) {
    visibility[t] = 0.0;
    if (sum) sum[t] = Eigen::Vector3d::Zero();
  }
  for (int d = 0; d < directions; ++d) {
    FrameSlice& slice = slices[d];
    std::array<std::array<double, kMaxThins>, 2> c;
    for (int side = 0; side < 2; ++side) {
      const double sign = side == 0 ? -1.0 : 1.0;
      const double low_cos = side == 0 ? slice.slice.sin_n : -slice.slice.sin_n;  // cos(n ± π/2)
      sideHorizonCos(image, i, j, px.x, px.v, slice.slice.omega, sign, low_cos, offsets.data(),
                     group.steps, falloff, group.thins, c[side].data());
    }
    // Per thread: an Angle array of the frame would set every element's default on each call.
    thread_local std::array<std::array<Angle, 2>, kMaxThins> h;
    for (std::size_t t = 0; t < thins; ++t) {
      for (int side = 0; side < 2; ++side) {
        // Thin compensations whose samples blend alike have the same cos, so the same horizon.
        std::size_t same = 0;
        while (same < t && c[side][same] != c[side][t]) ++same;
        h[t][side] = same < t ? h[same][side] : sideHorizon(c[side][t], side, &slice);
      }
      accumulateSlice(slice.slice, h[t].data(), px.v, &visibility[t], sum ? &sum[t] : nullptr);
    }
  }
}

// Pass 1 of one frame at pixel p for every run, stored as RGBA8 into (*out)[run][p]: the slices
// once, each group's samples once and each of its thin compensations' horizons and their sum
// (visibility and, unless kAoOnly leaves RGB 0, the unnormalised view-space bent normal), then
// each run's intensity power.
void framePixel(const GBuffer& g, const SampleImage& image, int i, int j, std::size_t p,
                const PixelSetup& px, int frame, const std::vector<GtaoRuntimeSettings>& runs,
                const std::vector<HorizonGroup>& groups, EstimateParts parts,
                std::vector<Rgba8Image>* out) {
  const bool with_bent = parts == EstimateParts::kAoAndBent;
  const int directions = runs.front().directions;
  const double base_noise = frameNoise(px.ign, frame);
  const double step_noise = fract(base_noise * 0.7 + 0.15);
  // Per thread: a Slice array of the frame would set all kMaxDirections elements' defaults.
  thread_local std::array<FrameSlice, kMaxDirections> slices;
  for (int d = 0; d < directions; ++d) {
    // sliceAlong without its angle, from the pixel's image point and offset.
    const Eigen::Vector3d o = tangentDirection(px.v, kPi * (d + base_noise) / directions);
    constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
    slices[d] = {sliceThroughWithoutAngle(px.v, o, px.normal,
                                          imageDirection(g, px.x, px.from, px.offset, o)),
                 false,
                 {kNone, kNone},
                 {}};
  }
  for (const HorizonGroup& group : groups) {
    std::array<double, kMaxThins> visibility;
    std::array<Eigen::Vector3d, kMaxThins> sum;
    groupHorizons(g, image, i, j, p, px, slices.data(), directions, step_noise, group,
                  visibility.data(), with_bent ? sum.data() : nullptr);
    for (std::size_t t = 0; t < group.thins.size(); ++t) {
      std::array<std::uint8_t, 4> bytes = {0, 0, 0, 0};
      if (with_bent) {
        Eigen::Vector3d bent = sum[t].norm() > 1e-12 ? sum[t] : px.normal;  // degenerate: N
        bent.normalize();
        bytes = {unorm8(bent.x() * 0.5 + 0.5), unorm8(bent.y() * 0.5 + 0.5),
                 unorm8(bent.z() * 0.5 + 0.5), 0};
      }
      const double open = std::clamp(visibility[t] / directions, 0.0, 1.0);
      for (std::size_t r : group.runs[t]) {
        // x¹ is x itself (pow's result is within an ulp of the exact one, here representable).
        const double intensity = runs[r].intensity;
        bytes[3] = unorm8(intensity == 1.0 ? open : std::pow(open, intensity));
        (*out)[r][p] = bytes;
      }
    }
  }
}

}  // namespace

void validate(const GtaoRuntimeSettings& s) {
  if (!(s.radius > 0.0) || !std::isfinite(s.radius)) {
    throw Error("gtao-runtime: radius must be a positive finite distance in metres");
  }
  if (s.directions < 1 || s.directions > kMaxDirections)
    throw Error("gtao-runtime: directions must be in [1, 64]");
  if (s.steps < 1 || s.steps > kMaxSteps) throw Error("gtao-runtime: steps must be in [1, 256]");
  if (!(s.thin_compensation >= 0.0 && s.thin_compensation <= 10.0)) {
    throw Error("gtao-runtime: thin_compensation must be in [0, 10]");
  }
  if (!(s.intensity > 0.0 && s.intensity <= 16.0)) {
    throw Error("gtao-runtime: intensity must be in (0, 16]");
  }
  if (!(s.temporal_blend >= 0.0 && s.temporal_blend < 1.0)) {
    throw Error("gtao-runtime: temporal_blend must be in [0, 1)");
  }
  if (s.frames < 1 || s.frames > 1024) throw Error("gtao-runtime: frames must be in [1, 1024]");
}

double interleavedGradientNoise(int x, int y) {
  return fract(52.9829189 * fract(0.06711056 * x + 0.00583715 * y));
}

double frameNoise(double ign, int frame) {
  return fract(ign + (frame % 64) * kGoldenRatioFraction);
}

Eigen::Vector3d r10g10b10Normal(const Eigen::Vector3d& n) {
  Eigen::Vector3d d;
  for (int c = 0; c < 3; ++c) {
    const double code = std::round(std::clamp(n[c] * 0.5 + 0.5, 0.0, 1.0) * 1023.0);
    d[c] = code / 1023.0 * 2.0 - 1.0;
  }
  return d.normalized();
}

AoEstimate gtaoRuntime(const GBuffer& g, const GtaoRuntimeSettings& s) {
  return std::move(gtaoRuntimeRuns(g, {s}).front());
}

std::vector<AoEstimate> gtaoRuntimeRuns(const GBuffer& g,
                                        const std::vector<GtaoRuntimeSettings>& runs,
                                        EstimateParts parts) {
  if (runs.empty()) return {};
  for (const GtaoRuntimeSettings& s : runs) {
    validate(s);
    if (s.directions != runs.front().directions || s.frames != runs.front().frames) {
      throw Error("gtao-runtime: runs computed together must share directions and frames");
    }
  }
  const std::vector<PixelSetup> pixels = pixelSetup(g);
  const std::vector<HorizonGroup> groups = horizonGroups(runs);
  const FilterSetup filters = filterSetup(g);
  const SampleImage image(g);
  std::vector<Rgba8Image> history(runs.size());
  for (int frame = 0; frame < runs.front().frames; ++frame) {
    std::vector<Rgba8Image> current(runs.size(), Rgba8Image(g.pixels(), {0, 0, 0, 0}));
    forEachMaskedPixel(g, [&](int i, int j, std::size_t p) {
      framePixel(g, image, i, j, p, pixels[p], frame, runs, groups, parts, &current);
    });
    for (std::size_t r = 0; r < runs.size(); ++r) {
      if (runs[r].blur) current[r] = bilateralBlur(g, filters, current[r], parts);
      history[r] = temporalFilter(g, filters, current[r], history[r],
                                  frame == 0 ? 0.0 : runs[r].temporal_blend, parts);
    }
  }
  std::vector<AoEstimate> out;
  for (const Rgba8Image& image : history) out.push_back(decodeRgba8(g, image, parts));
  return out;
}

}  // namespace gtbake
