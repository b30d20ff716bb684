// The specular occlusion a runtime would compute at each path-traced pixel, by every method
// validate-gtso scores (docs/validate_gtso.md §1), and the error statistics against the truth.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "common/math_constants.h"
#include "common/progress.h"
#include "validate_gtso/gtso_lookup.h"
#include "validate_gtso/specular_sweep.h"

namespace gtbake {

// One evaluation point: an unmasked pixel at one roughness of the sweep.
struct SpecularSample {
  int scene = 0;
  int roughness = 0;  // index into SpecularSweep::roughness
  std::size_t pixel = 0;
  float A = 0.0f;
  float r_p = 0.0f;
  float n_dot_v = 0.0f;   // = cos θo = n·ωr
  float cos_beta = 0.0f;  // b·ωr, ωr = 2(n·ωo)n − ωo
  float n_dot_b = 0.0f;   // b·n
  double alpha_v = 0.0;   // visibility cone: cos αv = √(1 − A)
  double beta = 0.0;      // angle(b, ωr)
  double cos_av = 1.0, sin_av = 0.0, cos_b = 1.0, sin_b = 0.0;  // std::cos/sin of αv and β
  double out_of_plane = 0.0;  // degrees between b and the plane of n and ωr
  double truth = 0.0;         // path-traced S
  double noise_var = 0.0;     // (H0 − H1)²/4: its Monte Carlo variance, per pixel
};

// Sets s's visibility-cone and reflection angles from A and β: alpha_v, beta, cos_beta and the
// cached std::cos/sin of both (what the cone methods read).
void setConeAngles(SpecularSample* s, double beta);

std::vector<SpecularSample> gatherSamples(const SpecularSweep& sweep);

enum class Method {
  kS3Bc4,
  kS4Bc4,
  kS3Float,
  kS4Float,
  kS3R16,  // the R16_UNORM and R8_UNORM volumes export writes beside BC4
  kS4R16,
  kS3R8,
  kS4R8,
  kS3ClosedForm,  // gtsoS3ClosedForm with gtso.json closed_form's coefficients
  kConeTableFitU,
  kConePaperU,
  kConeUludagU,
  kConeFittedU,
  kConeFittedPerceptual,
  kNone,
  kAo,
  kLagarde,
  // The runtime pass's GTSO mode (docs/validate_gtso.md §1): the cone-to-cone value floored at A²
  // (its "ao² grazing-angle compensation"), at u = 0.01 and at the fitted u.
  kConeAo2PaperU,
  kConeAo2FittedU,
  kConeUserU,  // --u U (scored only when given)
};
inline constexpr int kMethodCount = 20;
const char* methodName(Method m);         // JSON key, e.g. "S4_bc4"
const char* methodDescription(Method m);  // one line for the page

// The u values the cone methods use.
struct ConeConstants {
  double table_fit = 0.0;          // gtso.json cone.u (fitted against S₃)
  double fitted = 0.0;             // fitted here, docs/gtso.md §1 convention u^(α²/2)
  double fitted_perceptual = 0.0;  // fitted here, perceptual reading u^(r_p²/2)
  double user = 0.0;               // --u (0: not scored)
};

// The specular cone αs of cos αs = u^(w²/2) (gtso::specularConeAperture) with its cos, sin and
// cap solid angle, computed once per (u, roughness).
struct ConeAperture {
  double a = 0.0, c = 1.0, s = 0.0, cap = 0.0;
};
ConeAperture coneAperture(double u, double w);
// What the cone model needs of one sample that does not depend on u, in one 64-byte record (the
// u scans of cone_u_fit and u_scene_interval stream millions of them per u): αv, β, their cos and
// sin, the visibility cap's solid angle and the path-traced S.
struct ConeInput {
  double alpha_v = 0.0, beta = 0.0;
  double cos_av = 1.0, sin_av = 0.0, cos_b = 1.0, sin_b = 0.0;
  double cap_av = 0.0;  // gtso::capSolidAngle(αv)
  double truth = 0.0;
};
ConeInput coneInput(const SpecularSample& s);
// gtso::coneSpecularOcclusion(αv, αs, β) from the sample's precomputed trig: the same operations
// on the same values, so the same bits (tests/validate_gtso checks), at a fraction of the cost:
// gtso::capIntersectionSolidAngle and coneSpecularOcclusion, case for case. Inline, as the u
// scans call it about two billion times.
inline double coneAt(const ConeInput& x, const ConeAperture& s) {
  const double a1 = x.alpha_v;
  const double a2 = s.a;
  const double beta = x.beta;
  if (a2 <= 0.0) {
    if (beta < a1) return 1.0;
    return beta == a1 ? 0.5 : 0.0;
  }
  double omega;
  if (a1 <= 0.0 || beta >= a1 + a2) {
    omega = 0.0;
  } else if (beta <= std::abs(a1 - a2)) {
    omega = a1 < a2 ? x.cap_av : s.cap;
  } else if (a1 + a2 + beta >= 2.0 * kPi) {
    omega = x.cap_av + s.cap - 4.0 * kPi;
  } else {
    auto clampedAcos = [](double v) { return std::acos(std::clamp(v, -1.0, 1.0)); };
    const double c1 = x.cos_av, s1 = x.sin_av;
    const double c2 = s.c, s2 = s.s;
    const double cb = x.cos_b, sb = x.sin_b;
    const double lens = clampedAcos((cb - c1 * c2) / (s1 * s2));
    const double arc1 = clampedAcos((c2 - cb * c1) / (sb * s1));
    const double arc2 = clampedAcos((c1 - cb * c2) / (sb * s2));
    omega = std::max(0.0, 2.0 * (kPi - lens - c1 * arc1 - c2 * arc2));
  }
  return std::clamp(omega / s.cap, 0.0, 1.0);
}
double coneAt(const SpecularSample& s, const ConeAperture& aperture);
// S_cone at one sample: w = α = r_p² (perceptual = false) or w = r_p.
double coneAt(const SpecularSample& s, double u, bool perceptual);
// Lagarde and de Rousiers 2014 with r = α = r_p² (what Filament and HDRP pass), in float.
float lagarde(float n_dot_v, float A, float r_p);

// The runtime pass's GTSO mode: max(S_cone, A²).
double coneAo2(double cone, double A);

// The value of every method in `methods` at every sample: values[m][i] (the other methods' rows
// stay empty). progress (optional): one per sample.
std::vector<std::vector<float>> evaluateMethods(const std::vector<SpecularSample>& samples,
                                                const TablesLookups& tables,
                                                const ConeConstants& cones,
                                                const std::vector<Method>& methods,
                                                Progress* progress = nullptr);

struct ErrorStats {
  std::size_t count = 0;
  double sum = 0.0;   // Σ (method − truth)
  double sum2 = 0.0;  // Σ (method − truth)²
  double max_abs = 0.0;
  double noise = 0.0;  // Σ noise_var of the same samples
  void add(double error, double noise_var);
  void merge(const ErrorStats& o);
  double rmse() const;
  double meanSigned() const;
  // √(max(0, MSE − mean noise variance)): the RMSE with the truth's Monte Carlo noise removed.
  double rmseNoiseCorrected() const;
};

}  // namespace gtbake
