#include "gtso/ggx.h"

#include <algorithm>

#include "common/math_constants.h"

namespace gtbake::gtso {

namespace {
constexpr double kPiOver4 = kPi / 4.0;
}  // namespace

// pbrt-v4 SampleUniformDiskConcentric: the square's four triangular sectors |x| >< |y| map to
// four disk sectors, radius = the larger coordinate, angle linear in the smaller one.
Point2 sampleUniformDiskConcentric(Point2 u) {
  const double x = 2.0 * u.x - 1.0;
  const double y = 2.0 * u.y - 1.0;
  if (x == 0.0 && y == 0.0) return {0.0, 0.0};
  if (std::abs(x) > std::abs(y)) {
    const double theta = kPiOver4 * (y / x);
    return {x * std::cos(theta), x * std::sin(theta)};
  }
  const double theta = kPi / 2.0 - kPiOver4 * (x / y);
  return {y * std::cos(theta), y * std::sin(theta)};
}

// Inverse of the above: the radius gives the larger |coordinate|, the angle within the sector
// (atan of the coordinate ratio) gives the smaller one.
Point2 invertUniformDiskConcentric(Point2 p) {
  const double r = std::sqrt(p.x * p.x + p.y * p.y);
  double x = 0.0, y = 0.0;
  if (r > 0.0) {
    if (std::abs(p.x) >= std::abs(p.y)) {
      x = std::copysign(r, p.x);
      y = x * std::atan(p.y / p.x) / kPiOver4;
    } else {
      y = std::copysign(r, p.y);
      x = y * std::atan(p.x / p.y) / kPiOver4;
    }
  }
  return {0.5 * (x + 1.0), 0.5 * (y + 1.0)};
}

// D = alpha^2 / (pi (cos^2(theta_m) (alpha^2 - 1) + 1)^2), the same as the tan form in the header.
double GgxDistribution::D(Vec3 wm) const {
  if (wm.z <= 0.0) return 0.0;
  const double a2 = alpha_ * alpha_;
  const double t = wm.z * wm.z * (a2 - 1.0) + 1.0;
  return a2 / (kPi * t * t);
}

// Lambda = (sqrt(1 + x) - 1) / 2 = x / (2 (sqrt(1 + x) + 1)), x = alpha^2 tan^2(theta); the second
// form keeps full precision for tiny alpha. Infinite at the horizon.
double GgxDistribution::Lambda(Vec3 w) const {
  const double cos2 = w.z * w.z;
  if (cos2 == 0.0) return HUGE_VAL;
  const double tan2 = std::max(0.0, 1.0 - cos2) / cos2;
  const double x = alpha_ * alpha_ * tan2;
  return x / (2.0 * (std::sqrt(1.0 + x) + 1.0));
}

double GgxDistribution::D(Vec3 wo, Vec3 wm) const {
  return G1(wo) / std::abs(wo.z) * D(wm) * std::max(0.0, dot(wo, wm));
}

double GgxDistribution::f(Vec3 wo, Vec3 wi) const {
  if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
  const Vec3 wm = normalize(wo + wi);
  return D(wm) * G2(wo, wi) / (4.0 * wo.z * wi.z);
}

double GgxDistribution::pdfWi(Vec3 wo, Vec3 wi) const {
  const Vec3 h = wo + wi;
  if (dot(h, h) == 0.0) return 0.0;
  const Vec3 wm = normalize(h);
  const double cosOm = dot(wo, wm);
  return cosOm > 0.0 ? D(wo, wm) / (4.0 * cosOm) : 0.0;
}

double GgxDistribution::weight(double onePlusLambdaO, Vec3 wi) const {
  if (wi.z <= 0.0) return 0.0;
  return 1.0 / (1.0 + Lambda(wi) / onePlusLambdaO);
}

// The hemisphere configuration of wo (stretched to alpha = 1) and an orthonormal frame (T1, T2)
// around it, T1 horizontal; shared by sampleWm and its inverse so both use the same frame.
std::array<Vec3, 3> GgxDistribution::stretchedFrame(Vec3 wo) const {
  const Vec3 vh = normalize({alpha_ * wo.x, alpha_ * wo.y, wo.z});
  const double lensq = vh.x * vh.x + vh.y * vh.y;
  const Vec3 t1v =
      lensq > 0.0 ? (1.0 / std::sqrt(lensq)) * Vec3{-vh.y, vh.x, 0.0} : Vec3{1.0, 0.0, 0.0};
  return {vh, t1v, cross(vh, t1v)};
}

// Heitz 2018, Listing 1, with the concentric disk: stretch wo into the hemisphere configuration
// (alpha = 1), sample the projected visible hemisphere (a disk whose lower half is squashed by
// s = (1 + Vh.z) / 2), lift to the hemisphere, unstretch.
Vec3 GgxDistribution::sampleWm(Vec3 wo, Point2 u) const {
  const auto [vh, t1v, t2v] = stretchedFrame(wo);
  const Point2 p = sampleUniformDiskConcentric(u);
  const double t1 = p.x;
  const double s = 0.5 * (1.0 + vh.z);
  const double t2 = (1.0 - s) * std::sqrt(std::max(0.0, 1.0 - t1 * t1)) + s * p.y;
  const double tz = std::sqrt(std::max(0.0, 1.0 - t1 * t1 - t2 * t2));
  const Vec3 nh = t1 * t1v + t2 * t2v + tz * vh;
  return normalize({alpha_ * nh.x, alpha_ * nh.y, std::max(0.0, nh.z)});
}

// The steps of sampleWm run backwards: stretch wm back to the hemisphere configuration, project on
// (T1, T2), undo the squash of the lower half, invert the concentric map.
Point2 GgxDistribution::invertWm(Vec3 wo, Vec3 wm) const {
  const auto [vh, t1v, t2v] = stretchedFrame(wo);
  const Vec3 nh = normalize({wm.x / alpha_, wm.y / alpha_, wm.z});
  const double t1 = dot(nh, t1v);
  const double s = 0.5 * (1.0 + vh.z);
  const double t2 = (dot(nh, t2v) - (1.0 - s) * std::sqrt(std::max(0.0, 1.0 - t1 * t1))) / s;
  return invertUniformDiskConcentric({t1, t2});
}

}  // namespace gtbake::gtso
