#include "screen_ao/hbao.h"

#include "common/error.h"
#include "common/rng.h"
#include "screen_ao/sample_image.h"
#include "screen_ao/slice_geometry.h"

namespace gtbake {

namespace {

// sin t(θ): the elevation (above the plane ⊥ V) of the tangent plane's line in the slice, from the
// view ray through the image point one pixel along ω, intersected with the tangent plane.
double tangentSine(const GBuffer& g, int i, int j, const Eigen::Vector2d& omega,
                   const Eigen::Vector3d& x, const Eigen::Vector3d& v,
                   const Eigen::Vector3d& normal) {
  const double tan_half = g.tan_half;
  const double aspect = g.aspect;
  const double px = i + 0.5 + omega.x();
  const double py = j + 0.5 - omega.y();
  const Eigen::Vector3d ray((2.0 * px / g.width - 1.0) * tan_half * aspect,
                            (1.0 - 2.0 * py / g.height) * tan_half, -1.0);
  const double denominator = normal.dot(ray);
  Eigen::Vector3d tangent;
  if (std::abs(denominator) > 1e-12) {
    tangent = ray * (normal.dot(x) / denominator) - x;  // the plane point on that ray, minus P
  } else {
    tangent = ray;
  }
  if (!(tangent.norm() > 0.0)) return 0.0;
  return std::clamp(tangent.normalized().dot(v), -1.0, 1.0);
}

void hbaoPixel(const GBuffer& g, const SampleImage& image, int i, int j, std::size_t p,
               const HbaoSettings& s, const CounterRng& rng, double* a, Eigen::Vector3d* bent) {
  const auto [x, v, normal] = pixelFrame(g, p);
  const double radius_px = s.radius * g.pixelsPerMetre(g.depth[p]);
  const std::array<float, 4> u = rng.uniform4(p, 0);
  const double step_px = radius_px / s.steps;
  double occlusion = 0.0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int d = 0; d < s.directions; ++d) {
    const double theta = 2.0 * kPi * (d + u[0]) / s.directions;
    const Eigen::Vector2d omega(std::cos(theta), std::sin(theta));
    const double sin_t = tangentSine(g, i, j, omega, x, v, normal);
    double sin_h = sin_t;
    double r = 0.0;
    for (int k = 0; k < s.steps; ++k) {
      const double t = (k + u[1]) * step_px + 1.0;
      Eigen::Vector3d sample;
      if (!image.point(i + 0.5 + t * omega.x(), j + 0.5 - t * omega.y(), &sample)) continue;
      const Eigen::Vector3d delta = sample - x;
      const double length = delta.norm();
      if (length > s.radius || !(length > 0.0)) continue;
      const double sin_alpha = delta.dot(v) / length;
      if (sin_alpha > sin_h) {
        sin_h = sin_alpha;
        r = length;
      }
    }
    occlusion += (sin_h - sin_t) * std::max(0.0, 1.0 - r / s.radius);
    // Bent normal: the half slice towards ω, from V (θ = 0) to its horizon, whose angle from V has
    // cos θ = sin h (h is an elevation above the plane ⊥ V).
    const Slice slice = makeSlice(v, normal, omega);
    double t0 = 0.0;
    double t1 = 0.0;
    addBentSide(horizonOf(sin_h, 1, slice), slice.sin_n, slice.cos_n, &t0, &t1);
    sum += slice.projected_length * (t0 * slice.o + t1 * v);
  }
  *a = 1.0 - occlusion / s.directions;
  *bent = sum;
}

}  // namespace

void validate(const HbaoSettings& s) {
  if (!(s.radius > 0.0) || !std::isfinite(s.radius)) {
    throw Error("hbao: radius must be a positive finite distance in metres");
  }
  if (s.directions < 1 || s.directions > 1024) throw Error("hbao: directions must be in [1, 1024]");
  if (s.steps < 1 || s.steps > 4096) throw Error("hbao: steps must be in [1, 4096]");
}

AoEstimate hbao(const GBuffer& g, const HbaoSettings& s) {
  validate(s);
  const CounterRng rng(s.seed, 0x4842414fu);  // "HBAO"
  const SampleImage image(g);
  return estimatePerPixel(g, [&](int i, int j, std::size_t p, double* a, Eigen::Vector3d* bent) {
    hbaoPixel(g, image, i, j, p, s, rng, a, bent);
  });
}

}  // namespace gtbake
