#include "gtso/cone_intersection.h"

#include <algorithm>
#include <cmath>

#include "common/math_constants.h"

namespace gtbake::gtso {

namespace {

double clampedAcos(double x) {
  return std::acos(std::clamp(x, -1.0, 1.0));
}
}  // namespace

double capSolidAngle(double a) {
  const double s = std::sin(0.5 * a);
  return 4.0 * kPi * s * s;
}

double capIntersectionSolidAngle(double a1, double a2, double beta) {
  if (a1 <= 0.0 || a2 <= 0.0) return 0.0;
  if (beta >= a1 + a2) return 0.0;
  if (beta <= std::abs(a1 - a2)) return capSolidAngle(std::min(a1, a2));
  if (a1 + a2 + beta >= 2.0 * kPi) return capSolidAngle(a1) + capSolidAngle(a2) - 4.0 * kPi;
  const double c1 = std::cos(a1), s1 = std::sin(a1);
  const double c2 = std::cos(a2), s2 = std::sin(a2);
  const double cb = std::cos(beta), sb = std::sin(beta);
  const double lens = clampedAcos((cb - c1 * c2) / (s1 * s2));
  const double arc1 = clampedAcos((c2 - cb * c1) / (sb * s1));
  const double arc2 = clampedAcos((c1 - cb * c2) / (sb * s2));
  return std::max(0.0, 2.0 * (kPi - lens - c1 * arc1 - c2 * arc2));
}

double coneSpecularOcclusion(double alpha_v, double alpha_s, double beta) {
  if (alpha_s <= 0.0) {
    if (beta < alpha_v) return 1.0;
    return beta == alpha_v ? 0.5 : 0.0;
  }
  return std::clamp(capIntersectionSolidAngle(alpha_v, alpha_s, beta) / capSolidAngle(alpha_s), 0.0,
                    1.0);
}

// cos(alpha_s) = exp(w^2/2 ln u); alpha_s = 2 asin(sqrt((1 - cos)/2)) with 1 - cos = -expm1(...),
// exact for the tiny apertures of the smallest roughness texels.
double specularConeAperture(double u, double w) {
  const double oneMinusCos = -std::expm1(0.5 * w * w * std::log(u));
  return 2.0 * std::asin(std::sqrt(std::clamp(0.5 * oneMinusCos, 0.0, 1.0)));
}

}  // namespace gtbake::gtso
