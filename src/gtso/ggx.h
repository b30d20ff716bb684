// The isotropic GGX microfacet BRDF of docs/gtso.md §1 (F = 1) and its visible-normal sampler.
//
// Conventions: shading frame with the normal n = +z. Roughness is the perceptual roughness r_p and
// the GGX width is alpha = r_p^2 everywhere in gtbake; functions here take alpha (the width).
//
// clang-format off
//   D(wm)        = 1 / (pi alpha^2 cos^4(theta_m) (1 + tan^2(theta_m)/alpha^2)^2)   (Trowbridge-Reitz)
//   Lambda(w)    = (sqrt(1 + alpha^2 tan^2(theta)) - 1) / 2
//   G1(w)        = 1 / (1 + Lambda(w))
//   G2(wo, wi)   = 1 / (1 + Lambda(wo) + Lambda(wi))                               (height-correlated Smith)
//   fr(wo, wi)   = D(wm) G2(wo, wi) / (4 cos(theta_o) cos(theta_i)),  wm = normalize(wo + wi)
// clang-format on
//
// Sampler (pbrt-v4 style sample / pdf / inverse): the distribution of visible normals
// D_wo(wm) = G1(wo) max(0, wo.wm) D(wm) / cos(theta_o) (Heitz 2018, "Sampling the GGX
// Distribution of Visible Normals", JCGT 7(4)), with the disk sampled by the concentric map
// (Shirley & Chiu 1997). The GTSO integrator uses the stretch property behind this sampler
// (gtso_integrator.h); the sampler itself serves brute-force checks and tests.
#pragma once

#include <array>
#include <cmath>

namespace gtbake::gtso {

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;
};
inline Vec3 operator+(Vec3 a, Vec3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3 operator-(Vec3 a, Vec3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 operator*(double s, Vec3 a) {
  return {s * a.x, s * a.y, s * a.z};
}
inline double dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline Vec3 normalize(Vec3 a) {
  return (1.0 / std::sqrt(dot(a, a))) * a;
}
inline Vec3 reflect(Vec3 wo, Vec3 wm) {
  return 2.0 * dot(wo, wm) * wm - wo;
}

struct Point2 {
  double x = 0.0, y = 0.0;
};

// Concentric square-to-disk map [0,1)^2 -> unit disk (area preserving up to the factor pi) and its
// inverse.
Point2 sampleUniformDiskConcentric(Point2 u);
Point2 invertUniformDiskConcentric(Point2 p);

class GgxDistribution {
 public:
  explicit GgxDistribution(double alpha) : alpha_(alpha) {}
  double alpha() const { return alpha_; }

  double D(Vec3 wm) const;
  double Lambda(Vec3 w) const;
  double G1(Vec3 w) const { return 1.0 / (1.0 + Lambda(w)); }
  double G2(Vec3 wo, Vec3 wi) const { return 1.0 / (1.0 + Lambda(wo) + Lambda(wi)); }
  // D_wo(wm): the density of visible normals, per unit solid angle of wm.
  double D(Vec3 wo, Vec3 wm) const;
  // fr(wo, wi) with F = 1; 0 unless both directions are above the surface.
  double f(Vec3 wo, Vec3 wi) const;

  // Visible normal for the sample u in [0,1)^2, and its density D(wo, wm) / inverse.
  Vec3 sampleWm(Vec3 wo, Point2 u) const;
  double pdfWm(Vec3 wo, Vec3 wm) const { return D(wo, wm); }
  Point2 invertWm(Vec3 wo, Vec3 wm) const;

  // Reflected direction wi = reflect(wo, wm(u)); pdf(wi) = D(wo, wm) / (4 wo.wm) per solid angle.
  Vec3 sampleWi(Vec3 wo, Point2 u) const { return reflect(wo, sampleWm(wo, u)); }
  double pdfWi(Vec3 wo, Vec3 wi) const;

  // The estimator weight fr(wo,wi) cos(theta_i) / pdfWi(wo,wi) = G2(wo,wi) / G1(wo), written as
  // 1 / (1 + Lambda(wi) / (1 + Lambda(wo))) so that the grazing limit cos(theta_o) -> 0 gives 1;
  // 0 for wi below the horizon.
  double weight(Vec3 wo, Vec3 wi) const { return weight(1.0 + Lambda(wo), wi); }
  // The same with 1 + Lambda(wo) passed in, for callers that hoist it out of a loop over wi.
  double weight(double onePlusLambdaO, Vec3 wi) const;

 private:
  std::array<Vec3, 3> stretchedFrame(Vec3 wo) const;  // (Vh, T1, T2) of Heitz 2018
  double alpha_;
};

}  // namespace gtbake::gtso
