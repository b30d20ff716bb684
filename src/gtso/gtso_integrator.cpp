#include "gtso/gtso_integrator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numeric>

#include "common/math_constants.h"

namespace gtbake::gtso {

namespace {

constexpr double kMirrorTie = 1e-9;  // |wr.b - cos(alpha_v)| below this is "on the boundary"
constexpr double kHalfPi = kPi / 2.0;
// psi rows per phi column: psi spans pi/2 and phi pi (the lobe is symmetric in y), so this makes
// psi steps 4x finer than phi steps; t varies fastest along psi (the lobe's tails), and at a
// fixed triangle count 2:1 gave 4x lower max error than 1:2 (docs/gtso.md).
constexpr int kPsiCellsPerPhiCell = 2;

// First index j of the descending thresholds with cs[j] <= t (cs.size() if none).
std::size_t firstBelow(const std::vector<double>& cs, double t) {
  return static_cast<std::size_t>(
      std::lower_bound(cs.begin(), cs.end(), t, std::greater<double>()) - cs.begin());
}

// A convex polygon inside one triangle, in barycentric coordinates (l1, l2): the triangle's
// vertices are (0,0), (1,0), (0,1). At most 3 + 2 clips = 5 vertices.
struct Polygon {
  int n = 0;
  std::array<double, 8> l1{}, l2{};
};

// A linear function on the triangle, from its three vertex values.
struct Linear {
  double f0, d1, d2;
  Linear(double a, double b, double c) : f0(a), d1(b - a), d2(c - a) {}
  double operator()(const Polygon& p, int m) const { return f0 + p.l1[m] * d1 + p.l2[m] * d2; }
};

// Sutherland-Hodgman: the part of `in` where the linear function f >= c.
Polygon clip(const Polygon& in, const Linear& f, double c) {
  Polygon out;
  for (int m = 0; m < in.n; ++m) {
    const int q = (m + 1) % in.n;
    const double fp = f(in, m) - c, fq = f(in, q) - c;
    if (fp >= 0.0) {
      out.l1[out.n] = in.l1[m];
      out.l2[out.n] = in.l2[m];
      ++out.n;
    }
    if ((fp >= 0.0) != (fq >= 0.0)) {
      const double s = fp / (fp - fq);
      out.l1[out.n] = in.l1[m] + s * (in.l1[q] - in.l1[m]);
      out.l2[out.n] = in.l2[m] + s * (in.l2[q] - in.l2[m]);
      ++out.n;
    }
  }
  return out;
}

// Int_polygon f dA in barycentric area units (the whole triangle has area 1/2): a fan of
// triangles, each contributing its area times the mean of f at its corners (exact for linear f).
double integrate(const Polygon& p, const Linear& f) {
  double sum = 0.0;
  for (int m = 1; m + 1 < p.n; ++m) {
    const double a1 = p.l1[m] - p.l1[0], a2 = p.l2[m] - p.l2[0];
    const double b1 = p.l1[m + 1] - p.l1[0], b2 = p.l2[m + 1] - p.l2[0];
    const double area = 0.5 * std::abs(a1 * b2 - a2 * b1);
    sum += area * (f(p, 0) + f(p, m) + f(p, m + 1)) / 3.0;
  }
  return sum;
}

// The quadrature of the header for a lobe of GGX width alpha. cs: thresholds cos(alpha_v),
// sorted descending. Returns S[k * M + j] in the sorted order.
std::vector<double> lobeIntegral(double alpha, double cosThetaO, const std::vector<Vec3>& b,
                                 const std::vector<double>& cs, int cells) {
  const GgxDistribution ggx(alpha);
  const Vec3 wo = viewDirection(cosThetaO);
  const Vec3 vh = normalize({alpha * wo.x, alpha * wo.y, wo.z});
  const int nPsi = kPsiCellsPerPhiCell * cells, nPhi = cells;
  const int n1 = nPhi + 1;
  const std::size_t nv = static_cast<std::size_t>(n1) * (nPsi + 1);
  const std::size_t K = b.size(), M = cs.size();
  // psi = (pi/2)(1 - (1 - zeta)^p), p = 1 + sin^2(theta_o): uniform at normal view; toward
  // grazing the visible normals crowd at psi -> pi/2 (steep microfacets seen edge-on), where
  // tan(theta_m) = alpha tan(psi) varies fastest, so the grid is refined there.
  const double power = 1.0 + (1.0 - cosThetaO * cosThetaO);
  std::vector<double> weight(nv), height(nv), t(K * nv);
  std::vector<Vec3> dir(nv);
  std::vector<double> cosPhi(n1), sinPhi(n1);
  for (int i = 0; i < n1; ++i) {
    cosPhi[i] = std::cos(kPi * i / nPhi);
    sinPhi[i] = std::sin(kPi * i / nPhi);
  }
  for (int j = 0; j <= nPsi; ++j) {
    const double zeta = static_cast<double>(j) / nPsi;
    const double psi = kHalfPi * (1.0 - std::pow(1.0 - zeta, power));
    const double dpsi = power * std::pow(1.0 - zeta, power - 1.0);
    const double sinPsi = std::sin(psi), cosPsi = std::cos(psi);
    for (int i = 0; i < n1; ++i) {
      const std::size_t v = static_cast<std::size_t>(j) * n1 + i;
      const Vec3 nh = {sinPsi * cosPhi[i], sinPsi * sinPhi[i], cosPsi};
      const Vec3 wi = reflect(wo, normalize({alpha * nh.x, alpha * nh.y, nh.z}));
      weight[v] = ggx.weight(wo, wi) * std::max(0.0, dot(vh, nh)) * sinPsi * dpsi;
      height[v] = wi.z;
      dir[v] = wi;
      for (std::size_t k = 0; k < K; ++k) t[v * K + k] = dot(wi, b[k]);  // vertex-major
    }
  }
  std::vector<double> cumulative(K * (M + 1), 0.0), partial(K * M, 0.0);
  double denominator = 0.0;

  // A triangle clipped by the horizon (rare): general polygon clipping.
  auto clippedTriangle = [&](std::size_t va, std::size_t vb, std::size_t vc, const Linear& z) {
    Polygon poly;
    poly.n = 3;
    poly.l1 = {0.0, 1.0, 0.0};
    poly.l2 = {0.0, 0.0, 1.0};
    poly = clip(poly, z, 0.0);
    const Linear w(weight[va], weight[vb], weight[vc]);
    const double full = integrate(poly, w);
    denominator += full;
    for (std::size_t k = 0; k < K; ++k) {
      const Linear tl(t[va * K + k], t[vb * K + k], t[vc * K + k]);
      double tmin = tl(poly, 0), tmax = tmin;
      for (int m = 1; m < poly.n; ++m) {
        tmin = std::min(tmin, tl(poly, m));
        tmax = std::max(tmax, tl(poly, m));
      }
      const std::size_t jFull = firstBelow(cs, tmin);
      cumulative[k * (M + 1) + jFull] += full;
      for (std::size_t j = jFull; j-- > 0 && cs[j] < tmax;) {
        partial[k * M + j] += integrate(clip(poly, tl, cs[j]), w);
      }
    }
  };

  // A triangle above the horizon: with its vertices sorted by t (t0 <= t1 <= t2), the part
  // below a threshold c <= t1 is the corner triangle at vertex 0 with edge fractions
  // s01 = (c - t0)/(t1 - t0), s02 = (c - t0)/(t2 - t0), and the part above c > t1 is the corner
  // triangle at vertex 2; the integral of the linear W over a corner triangle is its area times
  // the mean of W at its corners.
  auto triangle = [&](std::size_t va, std::size_t vb, std::size_t vc) {
    const Linear z(height[va], height[vb], height[vc]);
    const double zb = z.f0 + z.d1, zc = z.f0 + z.d2;
    if (z.f0 <= 0.0 && zb <= 0.0 && zc <= 0.0) return;                        // W = 0 everywhere
    if (weight[va] == 0.0 && weight[vb] == 0.0 && weight[vc] == 0.0) return;  // Q = 0: invisible
    if (z.f0 < 0.0 || zb < 0.0 || zc < 0.0) return clippedTriangle(va, vb, vc, z);
    const double full = (weight[va] + weight[vb] + weight[vc]) / 6.0;
    denominator += full;
    // Curvature correction: the linear interpolant of the unit vectors wi has length
    // |wi_lin| = sqrt(1 - sum_{k<l} l_k l_l |w_k - w_l|^2), whose mean over the triangle is
    // ~ 1 - sum |w_k - w_l|^2 / 24, so t_lin underestimates t = wi.b by that factor and would
    // shrink every cone by O(h^2) (the dominant error for small cones). Dividing the vertex t by
    // the mean length removes the bias to leading order.
    const Vec3 dab = dir[va] - dir[vb], dbc = dir[vb] - dir[vc], dca = dir[vc] - dir[va];
    const double scale = 1.0 / (1.0 - (dot(dab, dab) + dot(dbc, dbc) + dot(dca, dca)) / 24.0);
    const double *ta = &t[va * K], *tb = &t[vb * K], *tc = &t[vc * K];
    for (std::size_t k = 0; k < K; ++k) {
      std::array<std::pair<double, double>, 3> v = {
          {{scale * ta[k], weight[va]}, {scale * tb[k], weight[vb]}, {scale * tc[k], weight[vc]}}};
      if (v[1].first < v[0].first) std::swap(v[0], v[1]);
      if (v[2].first < v[1].first) std::swap(v[1], v[2]);
      if (v[1].first < v[0].first) std::swap(v[0], v[1]);
      const auto [t0, w0] = v[0];
      const auto [t1, w1] = v[1];
      const auto [t2, w2] = v[2];
      const std::size_t jFull = firstBelow(cs, t0);
      cumulative[k * (M + 1) + jFull] += full;
      for (std::size_t j = jFull; j-- > 0 && cs[j] < t2;) {
        const double c = cs[j];
        if (c <= t1) {
          const double s01 = (c - t0) / (t1 - t0), s02 = (c - t0) / (t2 - t0);
          const double below = s01 * s02 * (3.0 * w0 + s01 * (w1 - w0) + s02 * (w2 - w0)) / 6.0;
          partial[k * M + j] += full - below;
        } else {
          const double s20 = (t2 - c) / (t2 - t0), s21 = (t2 - c) / (t2 - t1);
          partial[k * M + j] += s20 * s21 * (3.0 * w2 + s20 * (w0 - w2) + s21 * (w1 - w2)) / 6.0;
        }
      }
    }
  };

  for (int j = 0; j < nPsi; ++j) {
    for (int i = 0; i < nPhi; ++i) {
      const std::size_t v00 = static_cast<std::size_t>(j) * n1 + i, v10 = v00 + 1;
      const std::size_t v01 = v00 + n1, v11 = v01 + 1;
      triangle(v00, v10, v11);
      triangle(v00, v11, v01);
    }
  }

  std::vector<double> s(K * M, 0.0);
  for (std::size_t k = 0; k < K; ++k) {
    double running = 0.0;
    for (std::size_t j = 0; j < M; ++j) {
      running += cumulative[k * (M + 1) + j];
      s[k * M + j] = denominator > 0.0
                         ? std::clamp((running + partial[k * M + j]) / denominator, 0.0, 1.0)
                         : 0.0;
    }
  }
  return s;
}

}  // namespace

Vec3 viewDirection(double cosThetaO) {
  const double c = std::clamp(cosThetaO, 0.0, 1.0);
  return {std::sqrt(std::max(0.0, 1.0 - c * c)), 0.0, c};
}

Vec3 bentNormal(double thetaO, double beta) {
  return {-std::sin(thetaO - beta), 0.0, std::cos(thetaO - beta)};
}

std::vector<double> specularOcclusion(double r_p, double cosThetaO, const std::vector<Vec3>& b,
                                      const std::vector<double>& cosAlphaV, int cells) {
  const std::size_t K = b.size(), M = cosAlphaV.size();
  std::vector<std::size_t> order(M);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return cosAlphaV[x] > cosAlphaV[y]; });
  std::vector<double> cs(M);
  for (std::size_t j = 0; j < M; ++j) cs[j] = cosAlphaV[order[j]];

  std::vector<double> out(K * M, 0.0);
  if (r_p > 0.0) {
    const std::vector<double> s = lobeIntegral(r_p * r_p, cosThetaO, b, cs, cells);
    // A cone of zero aperture (A = 0) holds no solid angle: exactly 0, whatever the curvature
    // correction does to t near 1.
    for (std::size_t k = 0; k < K; ++k) {
      for (std::size_t j = 0; j < M; ++j) out[k * M + order[j]] = cs[j] >= 1.0 ? 0.0 : s[k * M + j];
    }
    return out;
  }
  // Mirror limit: the lobe is the delta at wr, so S = DeltaV(wr) = [angle(wr, b) <= alpha_v]
  // (SPEC §1.4; the boundary belongs to the cone, with a tie tolerance for rounding in wr.b).
  // A cone of zero aperture (A = 0) holds no solid angle: 0, as for every r_p > 0.
  const Vec3 wo = viewDirection(cosThetaO);
  const Vec3 wr = {-wo.x, 0.0, wo.z};
  for (std::size_t k = 0; k < K; ++k) {
    const double tr = dot(wr, b[k]);
    for (std::size_t j = 0; j < M; ++j) {
      const double c = cosAlphaV[j];
      out[k * M + j] = (c < 1.0 && tr >= c - kMirrorTie) ? 1.0 : 0.0;
    }
  }
  return out;
}

}  // namespace gtbake::gtso
