// The slice geometry every horizon-based estimator shares (docs/screen_ao.md, "Slices").
//
// A slice is the plane through the view-space point P that holds the view vector V = −P/|P| and
// the image-plane direction ω = (cos φ, sin φ) (view space (cos φ, sin φ, 0)). Angles θ in it are
// measured from V, positive towards o, the unit part of (ω, 0) orthogonal to V. The normal N
// projects to N' = N − a(N·a), a = unit (ω, 0) × V; n is the signed angle from V to N' and |N'|
// its length (Timonen's and the paper's projected-normal correction, Eq. 8).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/math_constants.h"
#include "screen_ao/gbuffer.h"

namespace gtbake {

struct Slice {
  Eigen::Vector2d omega;          // image-plane direction (x right, y up)
  Eigen::Vector3d o;              // unit, in the slice, orthogonal to V, towards +ω
  double projected_length = 0.0;  // |N'|
  double n = 0.0;                 // signed angle from V to N'
  double sin_n = 0.0;
  double cos_n = 1.0;
};

// An angle with its sine and cosine: the slice integrals below need no other trigonometry.
struct Angle {
  double a = 0.0;
  double s = 0.0;
  double c = 1.0;
};

inline Angle angleOf(double a) {
  return {a, std::sin(a), std::cos(a)};
}

// The slice through V and the unit o ⊥ V, with image-plane direction omega, but for its angle n,
// left 0 (withAngle adds it): a caller that needs n only where a horizon may be clamped saves the
// atan2 elsewhere.
inline Slice sliceThroughWithoutAngle(const Eigen::Vector3d& v, const Eigen::Vector3d& o,
                                      const Eigen::Vector3d& normal, const Eigen::Vector2d& omega) {
  Slice s;
  s.omega = omega;
  s.o = o;
  const Eigen::Vector3d axis = o.cross(v).normalized();
  const Eigen::Vector3d projected = normal - axis * normal.dot(axis);
  s.projected_length = projected.norm();
  if (s.projected_length <= 0.0) return s;
  s.cos_n = projected.dot(v) / s.projected_length;
  s.sin_n = s.o.dot(projected) / s.projected_length;
  return s;
}

// The slice's n from its sine and cosine (0 where N' vanishes).
inline Slice withAngle(Slice s) {
  if (s.projected_length > 0.0) s.n = std::atan2(s.sin_n, s.cos_n);
  return s;
}

// The slice through V and the unit o ⊥ V, with image-plane direction omega.
inline Slice sliceThrough(const Eigen::Vector3d& v, const Eigen::Vector3d& o,
                          const Eigen::Vector3d& normal, const Eigen::Vector2d& omega) {
  return withAngle(sliceThroughWithoutAngle(v, o, normal, omega));
}

// The slice of image-plane angle φ (HBAO's parametrisation: uniform in the image, so not uniform
// about V away from the image centre), given by omega = (cos φ, sin φ).
inline Slice makeSlice(const Eigen::Vector3d& v, const Eigen::Vector3d& normal,
                       const Eigen::Vector2d& omega) {
  const Eigen::Vector3d d(omega.x(), omega.y(), 0.0);
  return sliceThrough(v, (d - d.dot(v) * v).normalized(), normal, omega);
}

// The unit image direction in which P + offset·o moves from P's image point `from` (screen x
// right, y up).
inline Eigen::Vector2d imageDirection(const GBuffer& g, const Eigen::Vector3d& x,
                                      const Eigen::Vector2d& from, double offset,
                                      const Eigen::Vector3d& o) {
  const Eigen::Vector2d to = g.project(x + offset * o);
  return Eigen::Vector2d(to.x() - from.x(), from.y() - to.y()).normalized();
}

// The slice of angle ψ about V (Eq. 5's parametrisation, uniform about V): o = cos ψ e1 + sin ψ e2
// with e1 the view x axis made orthogonal to V and e2 = V × e1; omega is the image direction in
// which P + εo moves, ε = 10⁻³|P|.
inline Slice sliceAlong(const GBuffer& g, const Eigen::Vector3d& x, const Eigen::Vector3d& v,
                        const Eigen::Vector3d& normal, const Eigen::Vector3d& o) {
  return sliceThrough(v, o, normal, imageDirection(g, x, g.project(x), 1e-3 * x.norm(), o));
}

// What makeViewSlice computes once per pixel: the basis e1, e2 about V, P's image point and the
// offset 10⁻³|P| along o at which sliceAlong finds the slice's image direction.
struct ViewSliceBasis {
  Eigen::Vector3d e1, e2;
  Eigen::Vector2d from;
  double offset = 0.0;
};
inline ViewSliceBasis viewSliceBasis(const GBuffer& g, const Eigen::Vector3d& x,
                                     const Eigen::Vector3d& v) {
  ViewSliceBasis b;
  b.e1 = (Eigen::Vector3d::UnitX() - v.x() * v).normalized();
  b.e2 = v.cross(b.e1);
  b.from = g.project(x);
  b.offset = 1e-3 * x.norm();
  return b;
}

// makeViewSlice from the pixel's basis, without n (sliceThroughWithoutAngle): the same operations
// as sliceAlong, so the same bits.
inline Slice viewSliceWithoutAngle(const GBuffer& g, const ViewSliceBasis& b,
                                   const Eigen::Vector3d& x, const Eigen::Vector3d& v,
                                   const Eigen::Vector3d& normal, const Angle& psi) {
  const Eigen::Vector3d o = psi.c * b.e1 + psi.s * b.e2;
  return sliceThroughWithoutAngle(v, o, normal, imageDirection(g, x, b.from, b.offset, o));
}

// The same for ψ given with its sine and cosine (angleOf(ψ)): a loop over pixels whose angles ψ
// are the same for every pixel takes them from a table made once.
inline Slice makeViewSlice(const GBuffer& g, const Eigen::Vector3d& x, const Eigen::Vector3d& v,
                           const Eigen::Vector3d& normal, const Angle& psi) {
  return withAngle(viewSliceWithoutAngle(g, viewSliceBasis(g, x, v), x, v, normal, psi));
}
inline Slice makeViewSlice(const GBuffer& g, const Eigen::Vector3d& x, const Eigen::Vector3d& v,
                           const Eigen::Vector3d& normal, double psi) {
  return makeViewSlice(g, x, v, normal, angleOf(psi));
}

// The tangent vector of image angle φ rotated to be orthogonal to V: the least rotation taking
// the view axis (0, 0, 1) to V (the memo's ROTFROMTOMATRIX, Alg. 2 line 7) applied to
// (cos φ, sin φ, 0). Even φ are even about V, so the slices are Eq. 5's.
inline Eigen::Vector3d tangentDirection(const Eigen::Vector3d& v, double phi) {
  const Eigen::Vector3d u(std::cos(phi), std::sin(phi), 0.0);
  const Eigen::Vector3d w(-v.y(), v.x(), 0.0);  // (0, 0, 1) × V
  return u + w.cross(u) + w.cross(w.cross(u)) / (1.0 + v.z());
}

// One side's cosine-weighted arc (paper Eq. 7, memo Alg. 1 line 28) for a signed horizon angle h:
// ∫ from 0 to h of cos(θ − n)|sin θ| dθ, = (cos n + 2h sin n − cos(2h − n))/4.
inline double arcIntegral(const Angle& h, double n_sin, double n_cos) {
  const double cos_2h_n = (h.c * h.c - h.s * h.s) * n_cos + 2.0 * h.s * h.c * n_sin;
  return 0.25 * (n_cos + 2.0 * h.a * n_sin - cos_2h_n);
}
inline double arcIntegral(double h, double n) {
  return arcIntegral(angleOf(h), std::sin(n), std::cos(n));
}

// The horizon angle of one side from its largest cos (memo Alg. 1 line 27): side 0 searches −ω
// (θ ≤ 0), side 1 +ω, clamped to the hemisphere [n − π/2, n + π/2] about N'.
inline double horizonAngle(double horizon_cos, int side, double n) {
  const double theta = (side == 0 ? -1.0 : 1.0) * std::acos(std::clamp(horizon_cos, -1.0, 1.0));
  return n + std::clamp(theta - n, -0.5 * kPi, 0.5 * kPi);
}

// The same with its sine and cosine (sin(n ± π/2) = ±cos n, cos(n ± π/2) = ∓sin n at the clamp).
inline Angle horizonOf(double horizon_cos, int side, const Slice& slice) {
  const double sign = side == 0 ? -1.0 : 1.0;
  const double c = std::clamp(horizon_cos, -1.0, 1.0);
  const double theta = sign * std::acos(c);
  if (theta - slice.n > 0.5 * kPi) return {slice.n + 0.5 * kPi, slice.cos_n, -slice.sin_n};
  if (theta - slice.n < -0.5 * kPi) return {slice.n - 0.5 * kPi, -slice.cos_n, slice.sin_n};
  return {theta, sign * std::sqrt(1.0 - c * c), c};
}

// Whether horizonOf(horizon_cos, side, slice) cannot clamp, so needs no slice.n (its atan2):
// floor_cos is the side's hemisphere end cos(n ∓ π/2) (−sin n on side 1, sin n on side 0). A
// horizon above it by 10⁻⁹ has an angle inside that end by more than 10⁻⁹ (|d acos/dc| ≥ 1), and
// cos n > 10⁻³ keeps n inside (−π/2, π/2) by as much, out of reach of the other end (θ has the
// side's sign). The rounding of acos, atan2 and of sin n, cos n (|d acos| ≤ 10³|d sin n| there)
// is below 10⁻¹², far inside both margins.
inline bool horizonUnclamped(double horizon_cos, double floor_cos, const Slice& slice) {
  return horizon_cos > floor_cos + 1e-9 && slice.cos_n > 1e-3;
}

// horizonOf's value where horizonUnclamped holds.
inline Angle unclampedHorizon(double horizon_cos, int side) {
  const double sign = side == 0 ? -1.0 : 1.0;
  const double c = std::clamp(horizon_cos, -1.0, 1.0);
  return {sign * std::acos(c), sign * std::sqrt(1.0 - c * c), c};
}

// One side's share of the slice's bent-normal integrals (memo Alg. 2, lines 4–5): t0 =
// ∫ cos(θ − n)|sin θ| sin θ dθ (along o) and t1 = ∫ cos(θ − n)|sin θ| cos θ dθ (along V) over
// [h0, h1] are sums of one term per horizon, each zero at h = 0; added to *t0, *t1.
inline void addBentSide(const Angle& h, double n_sin, double n_cos, double* t0, double* t1) {
  const double sin_3h = h.s * (3.0 - 4.0 * h.s * h.s);
  const double cos_3h = h.c * (4.0 * h.c * h.c - 3.0);
  const double sin_h_minus_n = h.s * n_cos - h.c * n_sin;
  const double sin_h_plus_n = h.s * n_cos + h.c * n_sin;
  const double cos_h_plus_n = h.c * n_cos - h.s * n_sin;
  const double sin_3h_minus_n = sin_3h * n_cos - cos_3h * n_sin;
  const double cos_3h_minus_n = cos_3h * n_cos + sin_3h * n_sin;
  *t0 += (6.0 * sin_h_minus_n - sin_3h_minus_n + 8.0 * n_sin - 3.0 * sin_h_plus_n) / 12.0;
  *t1 += (-cos_3h_minus_n + 4.0 * n_cos - 3.0 * cos_h_plus_n) / 12.0;
}

inline void bentIntegrals(double h0, double h1, double n, double* t0, double* t1) {
  const double n_sin = std::sin(n);
  const double n_cos = std::cos(n);
  *t0 = 0.0;
  *t1 = 0.0;
  addBentSide(angleOf(h0), n_sin, n_cos, t0, t1);
  addBentSide(angleOf(h1), n_sin, n_cos, t0, t1);
}

// Adds one slice with horizons h[0], h[1] to the running sums (memo Alg. 1 line 29, Alg. 2 line
// 6): the visibility |N'| (arc(h0) + arc(h1)) and, unless sum is null, the bent-normal direction
// |N'| (t0 o + t1 V), V the view vector.
inline void accumulateSlice(const Slice& slice, const Angle h[2], const Eigen::Vector3d& v,
                            double* visibility, Eigen::Vector3d* sum) {
  *visibility += slice.projected_length * (arcIntegral(h[0], slice.sin_n, slice.cos_n) +
                                           arcIntegral(h[1], slice.sin_n, slice.cos_n));
  if (sum == nullptr) return;
  double t0 = 0.0;
  double t1 = 0.0;
  addBentSide(h[0], slice.sin_n, slice.cos_n, &t0, &t1);
  addBentSide(h[1], slice.sin_n, slice.cos_n, &t0, &t1);
  *sum += slice.projected_length * (t0 * slice.o + t1 * v);
}

// The depth buffer's surface (docs/screen_ao.md §1): texel t holds, within its pixel, its tangent
// plane (its point T and normal N) clamped to the slab of depths within kPlaneReach footprints
// (Z·2tan(yfov/2)/H) of its own depth Z. The view ray r (z = −1) meets it at depth
// clamp(N·T/N·r, Z(1 − κ), Z(1 + κ)), κ = kPlaneReach·2tan(yfov/2)/H, where the plane's depth is
// +∞ if the ray meets the plane behind the camera or not at all. A planar surface is thus its own
// plane (the samples lie on the slice's line, so a plane yields exactly its tangent horizon), and
// a texel seen at a grazing angle is a short slab rather than a plane extrapolated far in depth;
// every ray through an unmasked texel meets its surface, so a silhouette has no gaps.
inline constexpr double kPlaneReach = 3.0;

// κ of the image (the slab's half-depth per metre of depth).
inline double slabReach(const GBuffer& g) {
  return kPlaneReach * 2.0 * g.tan_half / g.height;
}

inline double texelDepthOnRay(const Texel& t, const Eigen::Vector3d& ray, double reach) {
  const double k = t.normal[0] * static_cast<double>(t.position[0]) +
                   t.normal[1] * static_cast<double>(t.position[1]) +
                   t.normal[2] * static_cast<double>(t.position[2]);
  const double d = t.normal[0] * ray.x() + t.normal[1] * ray.y() + t.normal[2] * ray.z();
  const double plane = k * d > 0.0 ? k / d : std::numeric_limits<double>::infinity();
  const double z = t.depth;
  return std::clamp(plane, z * (1.0 - reach), z * (1.0 + reach));
}

// The view ray (z = −1) through the image point (x, y).
inline Eigen::Vector3d imageRay(const GBuffer& g, double x, double y) {
  return {(2.0 * x / g.width - 1.0) * g.tan_half * g.aspect,
          (1.0 - 2.0 * y / g.height) * g.tan_half, -1.0};
}

// The surface point seen through the image point (x, y), on the surface of the texel nearest to
// it; false off the image or where that texel is masked (sky: no occluder). `reach` is
// slabReach(g), which a loop over many samples computes once.
inline bool texelPlanePoint(const GBuffer& g, double x, double y, double reach,
                            Eigen::Vector3d* point) {
  const double fi = std::floor(x);
  const double fj = std::floor(y);
  if (fi < 0.0 || fj < 0.0 || fi >= g.width || fj >= g.height) return false;
  const Texel& t = g.texels[static_cast<std::size_t>(fj) * g.width + static_cast<std::size_t>(fi)];
  if (!(t.depth > 0.0f)) return false;
  const Eigen::Vector3d ray = imageRay(g, x, y);
  *point = texelDepthOnRay(t, ray, reach) * ray;
  return true;
}
inline bool texelPlanePoint(const GBuffer& g, double x, double y, Eigen::Vector3d* point) {
  return texelPlanePoint(g, x, y, slabReach(g), point);
}

// Pixel p's view-space point and normal.
inline Eigen::Vector3d viewPosition(const GBuffer& g, std::size_t p) {
  return Eigen::Vector3d(g.position[3 * p], g.position[3 * p + 1], g.position[3 * p + 2]);
}
inline Eigen::Vector3d viewNormal(const GBuffer& g, std::size_t p) {
  return Eigen::Vector3d(g.view_normal[3 * p], g.view_normal[3 * p + 1], g.view_normal[3 * p + 2]);
}

// What every horizon estimator starts a pixel from: P, the view direction V = −P/|P| and N.
struct PixelFrame {
  Eigen::Vector3d x, v, normal;
};
inline PixelFrame pixelFrame(const GBuffer& g, std::size_t p) {
  const Eigen::Vector3d x = viewPosition(g, p);
  return {x, -x.normalized(), viewNormal(g, p)};
}

}  // namespace gtbake
