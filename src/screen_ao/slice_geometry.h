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
};

// The slice through V and the unit o ⊥ V, with image-plane direction omega.
inline Slice sliceThrough(const Eigen::Vector3d& v, const Eigen::Vector3d& o,
                          const Eigen::Vector3d& normal, const Eigen::Vector2d& omega) {
  Slice s;
  s.omega = omega;
  s.o = o;
  const Eigen::Vector3d axis = o.cross(v).normalized();
  const Eigen::Vector3d projected = normal - axis * normal.dot(axis);
  s.projected_length = projected.norm();
  if (s.projected_length <= 0.0) return s;
  const double c = std::clamp(projected.dot(v) / s.projected_length, -1.0, 1.0);
  s.n = (s.o.dot(projected) < 0.0 ? -1.0 : 1.0) * std::acos(c);
  return s;
}

// The slice of image-plane angle φ (the runtime pass's and HBAO's parametrisation: uniform in the
// image, so not uniform about V away from the image centre).
inline Slice makeSlice(const Eigen::Vector3d& v, const Eigen::Vector3d& normal, double phi) {
  const Eigen::Vector2d omega(std::cos(phi), std::sin(phi));
  const Eigen::Vector3d d(omega.x(), omega.y(), 0.0);
  return sliceThrough(v, (d - d.dot(v) * v).normalized(), normal, omega);
}

// The slice of angle ψ about V (Eq. 5's parametrisation, uniform about V): o = cos ψ e1 + sin ψ e2
// with e1 the view x axis made orthogonal to V and e2 = V × e1; omega is the image direction in
// which P + εo moves (screen x right, y up).
inline Slice makeViewSlice(const GBuffer& g, const Eigen::Vector3d& x, const Eigen::Vector3d& v,
                           const Eigen::Vector3d& normal, double psi) {
  const Eigen::Vector3d e1 = (Eigen::Vector3d::UnitX() - v.x() * v).normalized();
  const Eigen::Vector3d e2 = v.cross(e1);
  const Eigen::Vector3d o = std::cos(psi) * e1 + std::sin(psi) * e2;
  const Eigen::Vector2d from = g.project(x);
  const Eigen::Vector2d to = g.project(x + 1e-3 * x.norm() * o);
  const Eigen::Vector2d omega = Eigen::Vector2d(to.x() - from.x(), from.y() - to.y()).normalized();
  return sliceThrough(v, o, normal, omega);
}

// One side's cosine-weighted arc (paper Eq. 7, memo Alg. 1 line 28) for a signed horizon angle h:
// ∫ from 0 to h of cos(θ − n)|sin θ| dθ, = (cos n + 2h sin n − cos(2h − n))/4.
inline double arcIntegral(double h, double n) {
  return 0.25 * (std::cos(n) + 2.0 * h * std::sin(n) - std::cos(2.0 * h - n));
}

// The horizon angle of one side from its largest cos (memo Alg. 1 line 27): side 0 searches −ω
// (θ ≤ 0), side 1 +ω, clamped to the hemisphere [n − π/2, n + π/2] about N'.
inline double horizonAngle(double horizon_cos, int side, double n) {
  const double theta = (side == 0 ? -1.0 : 1.0) * std::acos(std::clamp(horizon_cos, -1.0, 1.0));
  return n + std::clamp(theta - n, -0.5 * kPi, 0.5 * kPi);
}

// The slice's bent-normal integrals (memo Alg. 2, lines 4–5): t0 = ∫ cos(θ − n)|sin θ| sin θ dθ
// (along o) and t1 = ∫ cos(θ − n)|sin θ| cos θ dθ (along V), both over [h0, h1].
inline void bentIntegrals(double h0, double h1, double n, double* t0, double* t1) {
  // clang-format off
  *t0 = (6.0 * std::sin(h0 - n) - std::sin(3.0 * h0 - n) + 6.0 * std::sin(h1 - n) -
         std::sin(3.0 * h1 - n) + 16.0 * std::sin(n) - 3.0 * (std::sin(h0 + n) + std::sin(h1 + n))) /
        12.0;
  *t1 = (-std::cos(3.0 * h0 - n) - std::cos(3.0 * h1 - n) + 8.0 * std::cos(n) -
         3.0 * (std::cos(h0 + n) + std::cos(h1 + n))) /
        12.0;
  // clang-format on
}

// Adds one slice with horizon angles h[0], h[1] to the running sums (memo Alg. 1 line 29, Alg. 2
// line 6): the visibility |N'| (arc(h0) + arc(h1)) and the bent-normal direction
// |N'| (t0 o + t1 V), V the view vector.
inline void accumulateSlice(const Slice& slice, const double h[2], const Eigen::Vector3d& v,
                            double* visibility, Eigen::Vector3d* sum) {
  *visibility += slice.projected_length * (arcIntegral(h[0], slice.n) + arcIntegral(h[1], slice.n));
  double t0 = 0.0;
  double t1 = 0.0;
  bentIntegrals(h[0], h[1], slice.n, &t0, &t1);
  *sum += slice.projected_length * (t0 * slice.o + t1 * v);
}

// The view-space point of the texel nearest to the image point (x, y) (continuous pixel
// coordinates), or false off the image or where the pixel is masked (sky: no occluder).
inline bool texelPoint(const GBuffer& g, double x, double y, Eigen::Vector3d* point,
                       std::size_t* texel = nullptr) {
  const double fi = std::floor(x);
  const double fj = std::floor(y);
  if (fi < 0.0 || fj < 0.0 || fi >= g.width || fj >= g.height) return false;
  const std::size_t p = static_cast<std::size_t>(fj) * g.width + static_cast<std::size_t>(fi);
  const Texel& t = g.texels[p];
  if (t.valid == 0) return false;
  *point = Eigen::Vector3d(t.position[0], t.position[1], t.position[2]);
  if (texel != nullptr) *texel = p;
  return true;
}

// The surface point seen through the image point (x, y), from the texel nearest to it: where that
// point's view ray meets the texel's tangent plane (its position and normal), so samples lie on
// the slice's line exactly and a planar surface yields its own tangent horizon. False (no sample)
// off the image, where masked, where the ray grazes that plane (|N·r̂| < 0.05) or meets it farther
// than kPlaneReach texel footprints (Z·2tan(yfov/2)/H) from the texel's point: a plane
// extrapolated past its texel would invent occluders at silhouettes, and the texel's own point
// lies off the slice (a false horizon above a plane).
inline constexpr double kPlaneReach = 3.0;

inline bool texelPlanePoint(const GBuffer& g, double x, double y, Eigen::Vector3d* point) {
  std::size_t p = 0;
  if (!texelPoint(g, x, y, point, &p)) return false;
  const Eigen::Vector3d ray((2.0 * x / g.width - 1.0) * g.tan_half * g.aspect,
                            (1.0 - 2.0 * y / g.height) * g.tan_half, -1.0);  // z = −1
  const Texel& t = g.texels[p];
  const Eigen::Vector3d n(t.normal[0], t.normal[1], t.normal[2]);
  const double along = n.dot(ray);
  if (along * along < 0.0025 * ray.squaredNorm()) return false;
  const Eigen::Vector3d on_plane = (n.dot(*point) / along) * ray;
  const double footprint = 2.0 * g.tan_half * t.depth / g.height;
  if ((on_plane - *point).squaredNorm() > kPlaneReach * kPlaneReach * footprint * footprint) {
    return false;
  }
  *point = on_plane;
  return true;
}

// Calls f(x, y) at `per_texel` evenly spaced points ((k + ½)/per_texel) of the segment of the ray
// (x0, y0) + t(dx, dy), 0 < t ≤ length (image coordinates, (dx, dy) unit), inside every texel it
// crosses, nearest first (Amanatides–Woo traversal): no texel along the line is skipped, however
// thin.
template <typename F>
void forEachCrossedTexel(double x0, double y0, double dx, double dy, double length, int per_texel,
                         F f) {
  const double inf = std::numeric_limits<double>::infinity();
  double fx = std::floor(x0);
  double fy = std::floor(y0);
  const double step_x = dx > 0.0 ? 1.0 : -1.0;
  const double step_y = dy > 0.0 ? 1.0 : -1.0;
  const double delta_x = dx != 0.0 ? 1.0 / std::abs(dx) : inf;
  const double delta_y = dy != 0.0 ? 1.0 / std::abs(dy) : inf;
  double next_x = dx != 0.0 ? (dx > 0.0 ? fx + 1.0 - x0 : x0 - fx) * delta_x : inf;
  double next_y = dy != 0.0 ? (dy > 0.0 ? fy + 1.0 - y0 : y0 - fy) * delta_y : inf;
  double enter = 0.0;
  while (enter < length) {
    const double exit = std::min({next_x, next_y, length});
    for (int k = 0; k < per_texel; ++k) {
      const double t = enter + (k + 0.5) / per_texel * (exit - enter);
      f(x0 + t * dx, y0 + t * dy);
    }
    if (next_x < next_y) {
      fx += step_x;
      enter = next_x;
      next_x += delta_x;
    } else {
      fy += step_y;
      enter = next_y;
      next_y += delta_y;
    }
  }
}

// Pixel p's view-space point and normal.
inline Eigen::Vector3d viewPosition(const GBuffer& g, std::size_t p) {
  return Eigen::Vector3d(g.position[3 * p], g.position[3 * p + 1], g.position[3 * p + 2]);
}
inline Eigen::Vector3d viewNormal(const GBuffer& g, std::size_t p) {
  return Eigen::Vector3d(g.view_normal[3 * p], g.view_normal[3 * p + 1], g.view_normal[3 * p + 2]);
}

}  // namespace gtbake
