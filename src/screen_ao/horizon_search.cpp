#include "screen_ao/horizon_search.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace gtbake {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One side's search: the slice line's rays r(t) = r0 + t·r1 (view space, z = −1) at image
// parameter t, and the running horizon as key = cos·|cos| (monotone in cos, no square root).
class SideSearch {
 public:
  SideSearch(const HorizonPixel& p, const Eigen::Vector3d& r1, double reach, double floor_cos)
      : x_(p.x),
        v_(p.v),
        r0_(p.r0),
        r1_(r1),
        radius2_(p.radius * p.radius),
        reach_(reach),
        key_(floor_cos * std::abs(floor_cos)),
        rv0_(p.rv0),
        rv1_(r1.dot(p.v)),
        rx0_(p.rx0),
        rx1_(r1.dot(p.x)),
        rr0_(p.rr0),
        rr1_(p.r0.dot(r1)),
        rr2_(r1.squaredNorm()),
        xv_(p.xv),
        xx_(p.xx) {}

  double horizonCos() const { return std::copysign(std::sqrt(std::abs(key_)), key_); }

  // Raises the horizon to the texel's highest sample on [ta, tb]; true if it rose. Along the
  // segment the surface is at most three straight pieces (near face, plane, far face of the
  // slab), split where the plane's depth k/d crosses a face.
  bool visit(const Texel& texel, double ta, double tb) {
    near_ = texel.depth * (1.0 - reach_);
    if (belowHorizon(near_, ta) && belowHorizon(near_, tb)) {
      return false;
    }
    far_ = texel.depth * (1.0 + reach_);
    k_ = texel.normal[0] * static_cast<double>(texel.position[0]) +
         texel.normal[1] * static_cast<double>(texel.position[1]) +
         texel.normal[2] * static_cast<double>(texel.position[2]);
    const Eigen::Vector3d n(texel.normal[0], texel.normal[1], texel.normal[2]);
    alpha_ = n.dot(r0_);
    beta_ = n.dot(r1_);
    const double before = key_;
    // Common case: the plane is in front and inside the slab at both ends, hence in between.
    const double da = alpha_ + ta * beta_;
    const double db = alpha_ + tb * beta_;
    const double za = k_ / da;
    const double zb = k_ / db;
    if (za >= near_ && za <= far_ && zb >= near_ && zb <= far_) {
      piece(za * (r0_ + ta * r1_), zb * (r0_ + tb * r1_));
      return key_ > before;
    }
    double ts[4] = {ta, tb, tb, tb};
    int count = 1;
    if (beta_ != 0.0) {
      for (const double face : {near_, far_}) {
        const double t = (k_ / face - alpha_) / beta_;
        if (t > ta && t < tb) ts[count++] = t;
      }
      if (count == 3 && ts[2] < ts[1]) std::swap(ts[1], ts[2]);
    }
    ts[count++] = tb;
    Eigen::Vector3d a = point(ts[0]);
    for (int m = 1; m < count; ++m) {
      const Eigen::Vector3d b = point(ts[m]);
      piece(a, b);
      a = b;
    }
    return key_ > before;
  }

 private:
  // Whether the point s lies below the running horizon by more than a rounding margin. Every
  // sample of a texel lies in the slice plane on a view ray between its segment's ends, at a
  // depth in the slab [near, far]: a convex quadrilateral on one side of the line from P to the
  // camera, so its highest point seen from P is a corner; and along each view ray the point
  // nearer the camera is the higher. So when both near-face corners are below the horizon, no
  // sample of the texel can raise it and the texel is skipped (docs/screen_ao.md,
  // "gtao-reference"). Here s = z·r(t), u = s − P expanded in the per-side dot products; the 1e-9
  // margin, far above their rounding, keeps the result bit-identical to the full visit.
  bool belowHorizon(double z, double t) const {
    const double uv = z * (rv0_ + t * rv1_) - xv_;
    const double uu =
        z * (z * (rr0_ + t * (2.0 * rr1_ + t * rr2_)) - 2.0 * (rx0_ + t * rx1_)) + xx_;
    return uv * std::abs(uv) < (key_ - 1e-9) * uu;
  }
  Eigen::Vector3d point(double t) const {
    const Eigen::Vector3d r = r0_ + t * r1_;
    const double d = alpha_ + t * beta_;
    return std::clamp(k_ * d > 0.0 ? k_ / d : kInf, near_, far_) * r;
  }
  // The straight piece from a to b within the radius ball: its highest point is an end of the
  // part inside the ball (the angle seen from P is monotone along a line).
  void piece(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d ua = a - x_;
    const Eigen::Vector3d ub = b - x_;
    const double aa = ua.squaredNorm();
    const double bb = ub.squaredNorm();
    if (aa <= radius2_ && bb <= radius2_) {
      raise(ua, aa);
      raise(ub, bb);
      return;
    }
    const Eigen::Vector3d w = ub - ua;  // |ua + s w|² ≤ R², s ∈ [0, 1]
    const double ww = w.squaredNorm();
    const double uw = ua.dot(w);
    const double disc = uw * uw - ww * (aa - radius2_);
    if (!(disc > 0.0) || !(ww > 0.0)) return;
    const double root = std::sqrt(disc);
    const double s0 = std::max(0.0, (-uw - root) / ww);
    const double s1 = std::min(1.0, (-uw + root) / ww);
    if (!(s0 <= s1)) return;
    const Eigen::Vector3d u0 = ua + s0 * w;
    const Eigen::Vector3d u1 = ua + s1 * w;
    raise(u0, u0.squaredNorm());
    raise(u1, u1.squaredNorm());
  }
  // The sample at S = P + u: cos = u·v/|u|, compared as cos·|cos| without a division.
  void raise(const Eigen::Vector3d& u, double uu) {
    const double uv = u.dot(v_);
    if (uv * std::abs(uv) > key_ * uu && uu > 0.0) key_ = uv * std::abs(uv) / uu;
  }

  Eigen::Vector3d x_, v_, r0_, r1_;
  double radius2_, reach_;
  double key_;
  double rv0_, rv1_, rx0_, rx1_, rr0_, rr1_, rr2_, xv_, xx_;  // r(t)·v, r(t)·x, |r(t)|², x·v, |x|²
  double k_ = 0.0, alpha_ = 0.0, beta_ = 0.0, near_ = 0.0, far_ = 0.0;  // the current texel
};

// Whether texel t lies in the plane of the pixel's own texel (the same normal, the offset within
// 10⁻⁶): its samples lie on P's tangent plane, at or below the tangent horizon (the floor), so the
// search skips it, the pixel's own texel included. `tolerance` is the pixel's plane_tolerance.
bool coplanar(const Texel& t, const Texel& self, float tolerance) {
  return t.normal[0] == self.normal[0] && t.normal[1] == self.normal[1] &&
         t.normal[2] == self.normal[2] && std::abs(t.plane - self.plane) <= tolerance;
}

// Image parameter at which the line (x0, y0) + t(dx, dy) leaves the image.
double imageExit(const GBuffer& g, double x0, double y0, double dx, double dy) {
  double t = kInf;
  if (dx > 0.0) t = std::min(t, (g.width - x0) / dx);
  if (dx < 0.0) t = std::min(t, -x0 / dx);
  if (dy > 0.0) t = std::min(t, (g.height - y0) / dy);
  if (dy < 0.0) t = std::min(t, -y0 / dy);
  return t;
}

}  // namespace

HorizonPixel::HorizonPixel(const GBuffer& g, int i, int j, const Eigen::Vector3d& x,
                           const Eigen::Vector3d& v, double radius)
    : i(i),
      j(j),
      x(x),
      v(v),
      radius(radius),
      x0(i + 0.5),
      y0(j + 0.5),
      kx(2.0 * g.tan_half * g.aspect / g.width),
      ky(2.0 * g.tan_half / g.height),
      r0(kx * x0 - g.tan_half * g.aspect, g.tan_half - ky * y0, -1.0),
      distance(x.norm()),
      tangent_cos(radius / distance),
      rv0(r0.dot(v)),
      rx0(r0.dot(x)),
      rr0(r0.squaredNorm()),
      xv(x.dot(v)),
      xx(x.squaredNorm()),
      self(&g.texels[static_cast<std::size_t>(j) * g.width + i]),
      // Texels whose slab lies wholly outside the ball's depths [Z − R, Z + R] have no sample in
      // it.
      nearest((self->depth - radius) / (1.0 + slabReach(g))),
      farthest((self->depth + radius) / (1.0 - slabReach(g))),
      slab_reach(slabReach(g)),
      plane_tolerance(1e-6f * std::abs(self->plane)) {}

double exactHorizonCos(const GBuffer& g, int i, int j, const Eigen::Vector3d& x,
                       const Eigen::Vector3d& v, const Slice& slice, int side, double radius,
                       double floor_cos) {
  return exactHorizonCos(g, HorizonPixel(g, i, j, x, v, radius), slice, side, floor_cos);
}

double exactHorizonCos(const GBuffer& g, const HorizonPixel& p, const Slice& slice, int side,
                       double floor_cos) {
  const double sign = side == 0 ? -1.0 : 1.0;
  const double dx = sign * slice.omega.x();
  const double dy = -sign * slice.omega.y();  // image rows grow downwards
  const double x0 = p.x0;
  const double y0 = p.y0;
  const Eigen::Vector3d r1(p.kx * dx, -p.ky * dy, 0.0);
  const Eigen::Vector3d o = sign * slice.o;
  // Where the rays stop reaching a point of the ball above cos c: the ray through the ball's point
  // at angle acos(c) from V towards o, or through its tangent point (cos = R/|P|) for lower c.
  // Below the tangent ray's cos R/|P| the reach no longer depends on c. The horizon only rises
  // from floor_cos, so a horizon at or below it means floor_cos was too, and length already holds
  // that reach: it is recomputed only for horizons above the tangent ray.
  const double tangent_cos = p.tangent_cos;
  const auto reach = [&](double c) {
    if (!(p.distance > p.radius)) return kInf;
    const double q = std::max(c, tangent_cos);
    const Eigen::Vector3d point = p.x + p.radius * (std::sqrt(1.0 - q * q) * o + q * p.v);
    if (!(point.z() < 0.0)) return kInf;
    const Eigen::Vector2d s = g.project(point);
    return (s.x() - x0) * dx + (s.y() - y0) * dy;
  };
  SideSearch search(p, r1, p.slab_reach, floor_cos);
  double length = std::min(imageExit(g, x0, y0, dx, dy), reach(floor_cos));

  // Amanatides–Woo over the texels the line crosses, from the pixel's own outwards.
  const Texel& self = *p.self;
  const double nearest = p.nearest;
  const double farthest = p.farthest;
  int fx = p.i;
  int fy = p.j;
  const int step_x = dx > 0.0 ? 1 : -1;
  const int step_y = dy > 0.0 ? 1 : -1;
  // Each coordinate moves one way only, so once the line leaves the image it never returns: the
  // walk stops at the first column or row past the edge instead of stepping on over nothing.
  const int end_x = step_x > 0 ? g.width : -1;
  const int end_y = step_y > 0 ? g.height : -1;
  const std::ptrdiff_t row = step_y * static_cast<std::ptrdiff_t>(g.width);
  const Texel* texel = &self;
  const double delta_x = dx != 0.0 ? 1.0 / std::abs(dx) : kInf;
  const double delta_y = dy != 0.0 ? 1.0 / std::abs(dy) : kInf;
  double next_x = dx != 0.0 ? 0.5 * delta_x : kInf;
  double next_y = dy != 0.0 ? 0.5 * delta_y : kInf;
  double enter = 0.0;
  while (enter < length) {
    // Most texels skipped lie in the pixel's own plane, so that test goes first (the tests only
    // decide whether the texel is visited, so their order changes nothing else).
    const double depth = texel->depth;
    if (!coplanar(*texel, self, p.plane_tolerance) && depth > nearest && depth < farthest &&
        depth > 0.0 && search.visit(*texel, enter, std::min({next_x, next_y, length}))) {
      const double c = search.horizonCos();
      if (c > tangent_cos) length = std::min(length, reach(c));
    }
    if (next_x < next_y) {
      fx += step_x;
      if (fx == end_x) break;
      texel += step_x;
      enter = next_x;
      next_x += delta_x;
    } else {
      fy += step_y;
      if (fy == end_y) break;
      texel += row;
      enter = next_y;
      next_y += delta_y;
    }
  }
  return search.horizonCos();
}

}  // namespace gtbake
