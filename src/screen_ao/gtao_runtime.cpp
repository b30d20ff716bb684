#include "screen_ao/gtao_runtime.h"

#include "common/error.h"
#include "screen_ao/ao_filters.h"
#include "screen_ao/pixel_loop.h"
#include "screen_ao/slice_geometry.h"

namespace gtbake {

namespace {

double fract(double x) {
  return x - std::floor(x);
}

std::uint8_t unorm8(double x) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(x, 0.0, 1.0) * 255.0));
}

// Flat inside R(1 − 0.615), then linear to 0 at R.
double falloffWeight(double distance, double radius) {
  const double range = kFalloffRange * radius;
  const double from = radius * (1.0 - kFalloffRange);
  return std::clamp(1.0 - (distance - from) / range, 0.0, 1.0);
}

// One side's horizon cosine: quadratic steps t = ((k + noise)/steps)², each sample's cos blended
// towards the tangent plane's (low) horizon by the falloff weight, the falloff distance taken with
// the view-z part of the offset stretched by 1 + thin_compensation.
double sideHorizonCos(const GBuffer& g, int i, int j, const Eigen::Vector3d& x,
                      const Eigen::Vector3d& v, const Eigen::Vector2d& omega, double sign,
                      double low_cos, double radius_px, double step_noise,
                      const GtaoRuntimeSettings& s) {
  double horizon_cos = low_cos;
  for (int k = 0; k < s.steps; ++k) {
    const double linear = (k + step_noise) / s.steps;
    const double offset = std::max(1.0, linear * linear * radius_px);  // at least the next texel
    Eigen::Vector3d sample;
    if (!texelPlanePoint(g, i + 0.5 + sign * offset * omega.x(),
                         j + 0.5 - sign * offset * omega.y(), &sample)) {
      continue;
    }
    const Eigen::Vector3d d = sample - x;
    const double length = d.norm();
    if (!(length > 0.0)) continue;
    const Eigen::Vector3d stretched(d.x(), d.y(), d.z() * (1.0 + s.thin_compensation));
    const double weight = falloffWeight(stretched.norm(), s.radius);
    const double sample_cos = d.dot(v) / length;
    horizon_cos = std::max(horizon_cos, low_cos + (sample_cos - low_cos) * weight);
  }
  return horizon_cos;
}

}  // namespace

void validate(const GtaoRuntimeSettings& s) {
  if (!(s.radius > 0.0) || !std::isfinite(s.radius)) {
    throw Error("gtao-runtime: radius must be a positive finite distance in metres");
  }
  if (s.directions < 1 || s.directions > 64)
    throw Error("gtao-runtime: directions must be in [1, 64]");
  if (s.steps < 1 || s.steps > 256) throw Error("gtao-runtime: steps must be in [1, 256]");
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

double frameNoise(int x, int y, int frame) {
  return fract(interleavedGradientNoise(x, y) + (frame % 64) * kGoldenRatioFraction);
}

Eigen::Vector3d r10g10b10Normal(const Eigen::Vector3d& n) {
  Eigen::Vector3d d;
  for (int c = 0; c < 3; ++c) {
    const double code = std::round(std::clamp(n[c] * 0.5 + 0.5, 0.0, 1.0) * 1023.0);
    d[c] = code / 1023.0 * 2.0 - 1.0;
  }
  return d.normalized();
}

void gtaoRuntimePixel(const GBuffer& g, int i, int j, int frame, const GtaoRuntimeSettings& s,
                      double* ao, Eigen::Vector3d* bent) {
  const std::size_t p = static_cast<std::size_t>(j) * g.width + i;
  const Eigen::Vector3d x = viewPosition(g, p);
  const Eigen::Vector3d v = -x.normalized();
  const Eigen::Vector3d world(g.normal[3 * p], g.normal[3 * p + 1], g.normal[3 * p + 2]);
  const Eigen::Vector3d normal = g.worldToView(r10g10b10Normal(world));
  const double radius_px = s.radius * g.pixelsPerMetre(g.depth[p]);
  const double base_noise = frameNoise(i, j, frame);
  const double step_noise = fract(base_noise * 0.7 + 0.15);
  double visibility = 0.0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int d = 0; d < s.directions; ++d) {
    const Slice slice =
        sliceAlong(g, x, v, normal, tangentDirection(v, kPi * (d + base_noise) / s.directions));
    Angle h[2];
    for (int side = 0; side < 2; ++side) {
      const double sign = side == 0 ? -1.0 : 1.0;
      const double low_cos = side == 0 ? slice.sin_n : -slice.sin_n;  // cos(n ± π/2)
      const double c =
          sideHorizonCos(g, i, j, x, v, slice.omega, sign, low_cos, radius_px, step_noise, s);
      h[side] = horizonOf(c, side, slice);
    }
    accumulateSlice(slice, h, v, &visibility, &sum);
  }
  *ao = std::pow(std::clamp(visibility / s.directions, 0.0, 1.0), s.intensity);
  *bent = sum.norm() > 1e-12 ? sum : normal;  // degenerate: the surface normal
}

Rgba8Image gtaoRuntimeFrame(const GBuffer& g, int frame, const GtaoRuntimeSettings& s) {
  Rgba8Image out(g.pixels(), {0, 0, 0, 0});
  forEachMaskedPixel(g, [&](int i, int j, std::size_t p) {
    double ao = 0.0;
    Eigen::Vector3d bent;
    gtaoRuntimePixel(g, i, j, frame, s, &ao, &bent);
    bent.normalize();
    out[p] = {unorm8(bent.x() * 0.5 + 0.5), unorm8(bent.y() * 0.5 + 0.5),
              unorm8(bent.z() * 0.5 + 0.5), unorm8(ao)};
  });
  return out;
}

AoEstimate gtaoRuntime(const GBuffer& g, const GtaoRuntimeSettings& s) {
  validate(s);
  Rgba8Image history;
  for (int frame = 0; frame < s.frames; ++frame) {
    Rgba8Image current = gtaoRuntimeFrame(g, frame, s);
    if (s.blur) current = bilateralBlur(g, current);
    history = temporalFilter(g, current, history, frame == 0 ? 0.0 : s.temporal_blend);
  }
  return decodeRgba8(g, history);
}

}  // namespace gtbake
