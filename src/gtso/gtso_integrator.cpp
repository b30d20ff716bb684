#include "gtso/gtso_integrator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
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

// firstBelow(cs, t), trying `hint` first: neighbouring triangles mostly fall in the same bin.
// The hint is the answer exactly when it is the first index where cs[j] > t fails (the
// thresholds are sorted, so that index is unique).
std::size_t firstBelowFrom(const std::vector<double>& cs, double t, std::size_t hint) {
  if ((hint == cs.size() || !(cs[hint] > t)) && (hint == 0 || cs[hint - 1] > t)) return hint;
  return firstBelow(cs, t);
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

// The lobe grid of the header: vertex values of Q, z = wi.n and wi over the (zeta, phi)
// rectangle, 2*cells psi rows by cells phi columns.
struct LobeGrid {
  int nPsi = 0, nPhi = 0;
  std::vector<double> weight, height;
  std::vector<Vec3> dir;
  std::size_t vertices() const { return weight.size(); }
};

LobeGrid buildLobeGrid(double alpha, double cos_theta_o, int cells) {
  const GgxDistribution ggx(alpha);
  const Vec3 wo = viewDirection(cos_theta_o);
  const Vec3 vh = normalize({alpha * wo.x, alpha * wo.y, wo.z});
  LobeGrid g;
  g.nPsi = kPsiCellsPerPhiCell * cells;
  g.nPhi = cells;
  const int n1 = g.nPhi + 1;
  const std::size_t nv = static_cast<std::size_t>(n1) * (g.nPsi + 1);
  // Filled in vertex order below (push_back, not a zero-filled resize).
  g.weight.reserve(nv);
  g.height.reserve(nv);
  g.dir.reserve(nv);
  // psi = (pi/2)(1 - (1 - zeta)^p), p = 1 + sin^2(theta_o): uniform at normal view; toward
  // grazing the visible normals crowd at psi -> pi/2 (steep microfacets seen edge-on), where
  // tan(theta_m) = alpha tan(psi) varies fastest, so the grid is refined there.
  const double onePlusLambdaO = 1.0 + ggx.Lambda(wo);  // the same for every vertex
  const double power = 1.0 + (1.0 - cos_theta_o * cos_theta_o);
  std::vector<double> cosPhi(n1), sinPhi(n1);
  for (int i = 0; i < n1; ++i) {
    cosPhi[i] = std::cos(kPi * i / g.nPhi);
    sinPhi[i] = std::sin(kPi * i / g.nPhi);
  }
  for (int j = 0; j <= g.nPsi; ++j) {
    const double zeta = static_cast<double>(j) / g.nPsi;
    const double psi = kHalfPi * (1.0 - std::pow(1.0 - zeta, power));
    const double dpsi = power * std::pow(1.0 - zeta, power - 1.0);
    const double sinPsi = std::sin(psi), cosPsi = std::cos(psi);
    for (int i = 0; i < n1; ++i) {
      const Vec3 nh = {sinPsi * cosPhi[i], sinPsi * sinPhi[i], cosPsi};
      const Vec3 wi = reflect(wo, normalize({alpha * nh.x, alpha * nh.y, nh.z}));
      g.weight.push_back(ggx.weight(onePlusLambdaO, wi) * std::max(0.0, dot(vh, nh)) * sinPsi *
                         dpsi);
      g.height.push_back(wi.z);
      g.dir.push_back(wi);
    }
  }
  return g;
}

// Accumulates, for every bent normal k and each of its cone thresholds cs[k] (descending), the
// cumulative-sum bins and the clipped partial triangles; S follows from finish().
class ConeAccumulator {
 public:
  ConeAccumulator(const LobeGrid& grid, const std::vector<Vec3>& b,
                  const std::vector<std::vector<double>>& cs)
      : g_(grid), cs_(cs), K_(b.size()), t_(new double[K_ * grid.vertices()]) {
    for (std::size_t v = 0; v < grid.vertices(); ++v)
      for (std::size_t k = 0; k < K_; ++k) t_[v * K_ + k] = dot(grid.dir[v], b[k]);
    cumulative_.resize(K_);
    partial_.resize(K_);
    lastFull_.assign(K_, 0);
    for (std::size_t k = 0; k < K_; ++k) {
      cumulative_[k].assign(cs[k].size() + 1, 0.0);
      partial_[k].assign(cs[k].size(), 0.0);
    }
  }

  void addGrid() {
    const int n1 = g_.nPhi + 1;
    for (int j = 0; j < g_.nPsi; ++j) {
      for (int i = 0; i < g_.nPhi; ++i) {
        const std::size_t v00 = static_cast<std::size_t>(j) * n1 + i, v10 = v00 + 1;
        const std::size_t v01 = v00 + n1, v11 = v01 + 1;
        triangle(v00, v10, v11);
        triangle(v00, v11, v01);
      }
    }
  }

  std::vector<std::vector<double>> finish() const {
    std::vector<std::vector<double>> s(K_);
    for (std::size_t k = 0; k < K_; ++k) {
      double running = 0.0;
      s[k].assign(cs_[k].size(), 0.0);
      for (std::size_t j = 0; j < cs_[k].size(); ++j) {
        running += cumulative_[k][j];
        s[k][j] = denominator_ > 0.0
                      ? std::clamp((running + partial_[k][j]) / denominator_, 0.0, 1.0)
                      : 0.0;
      }
    }
    return s;
  }

 private:
  // A triangle above the horizon: with its vertices sorted by t (t0 <= t1 <= t2), the part
  // below a threshold c <= t1 is the corner triangle at vertex 0 with edge fractions
  // s01 = (c - t0)/(t1 - t0), s02 = (c - t0)/(t2 - t0), and the part above c > t1 is the corner
  // triangle at vertex 2; the integral of the linear W over a corner triangle is its area times
  // the mean of W at its corners.
  void triangle(std::size_t va, std::size_t vb, std::size_t vc) {
    const Linear z(g_.height[va], g_.height[vb], g_.height[vc]);
    const double zb = z.f0 + z.d1, zc = z.f0 + z.d2;
    if (z.f0 <= 0.0 && zb <= 0.0 && zc <= 0.0) return;  // W = 0 everywhere
    const double wa = g_.weight[va], wb = g_.weight[vb], wc = g_.weight[vc];
    if (wa == 0.0 && wb == 0.0 && wc == 0.0) return;  // Q = 0: invisible
    if (z.f0 < 0.0 || zb < 0.0 || zc < 0.0) return clippedTriangle(va, vb, vc, z);
    const double full = (wa + wb + wc) / 6.0;
    denominator_ += full;
    // Curvature correction: the linear interpolant of the unit vectors wi has length
    // |wi_lin| = sqrt(1 - sum_{k<l} l_k l_l |w_k - w_l|^2), whose mean over the triangle is
    // ~ 1 - sum |w_k - w_l|^2 / 24, so t_lin underestimates t = wi.b by that factor and would
    // shrink every cone by O(h^2) (the dominant error for small cones). Dividing the vertex t by
    // the mean length removes the bias to leading order.
    const Vec3 dab = g_.dir[va] - g_.dir[vb], dbc = g_.dir[vb] - g_.dir[vc];
    const Vec3 dca = g_.dir[vc] - g_.dir[va];
    const double scale = 1.0 / (1.0 - (dot(dab, dab) + dot(dbc, dbc) + dot(dca, dca)) / 24.0);
    const double *ta = &t_[va * K_], *tb = &t_[vb * K_], *tc = &t_[vc * K_];
    for (std::size_t k = 0; k < K_; ++k) {
      const std::vector<double>& cs = cs_[k];
      // t0 and t2 of the sort below are the smallest and largest t (finite: unit vectors and a
      // scale in [1, 1.6]); when no threshold lies in (t0, t2) the partial loop does nothing and
      // the sort by t is not needed.
      const double sa = scale * ta[k], sb = scale * tb[k], sc = scale * tc[k];
      const double s0 = std::min(std::min(sa, sb), sc), s2 = std::max(std::max(sa, sb), sc);
      const std::size_t jFull = firstBelowFrom(cs, s0, lastFull_[k]);
      lastFull_[k] = jFull;
      cumulative_[k][jFull] += full;
      if (jFull == 0 || !(cs[jFull - 1] < s2)) continue;
      std::array<std::pair<double, double>, 3> v = {{{sa, wa}, {sb, wb}, {sc, wc}}};
      if (v[1].first < v[0].first) std::swap(v[0], v[1]);
      if (v[2].first < v[1].first) std::swap(v[1], v[2]);
      if (v[1].first < v[0].first) std::swap(v[0], v[1]);
      const auto [t0, w0] = v[0];
      const auto [t1, w1] = v[1];
      const auto [t2, w2] = v[2];
      for (std::size_t j = jFull; j-- > 0 && cs[j] < t2;) {
        const double c = cs[j];
        if (c <= t1) {
          const double s01 = (c - t0) / (t1 - t0), s02 = (c - t0) / (t2 - t0);
          const double below = s01 * s02 * (3.0 * w0 + s01 * (w1 - w0) + s02 * (w2 - w0)) / 6.0;
          partial_[k][j] += full - below;
        } else {
          const double s20 = (t2 - c) / (t2 - t0), s21 = (t2 - c) / (t2 - t1);
          partial_[k][j] += s20 * s21 * (3.0 * w2 + s20 * (w0 - w2) + s21 * (w1 - w2)) / 6.0;
        }
      }
    }
  }

  // A triangle clipped by the horizon (rare): general polygon clipping.
  void clippedTriangle(std::size_t va, std::size_t vb, std::size_t vc, const Linear& z) {
    Polygon poly;
    poly.n = 3;
    poly.l1 = {0.0, 1.0, 0.0};
    poly.l2 = {0.0, 0.0, 1.0};
    poly = clip(poly, z, 0.0);
    const Linear w(g_.weight[va], g_.weight[vb], g_.weight[vc]);
    const double full = integrate(poly, w);
    denominator_ += full;
    for (std::size_t k = 0; k < K_; ++k) {
      const Linear tl(t_[va * K_ + k], t_[vb * K_ + k], t_[vc * K_ + k]);
      double tmin = tl(poly, 0), tmax = tmin;
      for (int m = 1; m < poly.n; ++m) {
        tmin = std::min(tmin, tl(poly, m));
        tmax = std::max(tmax, tl(poly, m));
      }
      const std::vector<double>& cs = cs_[k];
      const std::size_t jFull = firstBelow(cs, tmin);
      cumulative_[k][jFull] += full;
      for (std::size_t j = jFull; j-- > 0 && cs[j] < tmax;) {
        partial_[k][j] += integrate(clip(poly, tl, cs[j]), w);
      }
    }
  }

  const LobeGrid& g_;
  const std::vector<std::vector<double>>& cs_;
  std::size_t K_;
  // Vertex-major: t_[v * K + k] = wi(v).b[k]; every entry is written before it is read, so
  // the array is not zero-filled first (it is megabytes at the texel check's cells).
  std::unique_ptr<double[]> t_;
  std::vector<std::vector<double>> cumulative_, partial_;
  std::vector<std::size_t> lastFull_;  // per bent normal: the previous triangle's jFull
  double denominator_ = 0.0;
};

// The quadrature of the header for a lobe of GGX width alpha. cs[k]: thresholds cos(alpha_v) of
// bent normal k, sorted descending. Returns S[k][j] in the sorted order.
std::vector<std::vector<double>> lobeIntegral(double alpha, double cos_theta_o,
                                              const std::vector<Vec3>& b,
                                              const std::vector<std::vector<double>>& cs,
                                              int cells) {
  const LobeGrid grid = buildLobeGrid(alpha, cos_theta_o, cells);
  ConeAccumulator acc(grid, b, cs);
  acc.addGrid();
  return acc.finish();
}

}  // namespace

std::uint64_t lobeGridBytes(int cells, int normals) {
  const std::uint64_t vertices = (static_cast<std::uint64_t>(cells) + 1) *
                                 (static_cast<std::uint64_t>(kPsiCellsPerPhiCell) * cells + 1);
  return vertices * (2 * sizeof(double) + sizeof(Vec3) + sizeof(double) * normals);
}

Vec3 viewDirection(double cos_theta_o) {
  const double c = std::clamp(cos_theta_o, 0.0, 1.0);
  return {std::sqrt(std::max(0.0, 1.0 - c * c)), 0.0, c};
}

Vec3 bentNormal(double theta_o, double beta) {
  return {-std::sin(theta_o - beta), 0.0, std::cos(theta_o - beta)};
}

std::vector<std::vector<double>> specularOcclusion(
    double r_p, double cos_theta_o, const std::vector<Vec3>& b,
    const std::vector<std::vector<double>>& cos_alpha_v, int cells) {
  const std::size_t K = b.size();
  std::vector<std::vector<double>> out(K);
  if (r_p > 0.0) {
    std::vector<std::vector<std::size_t>> order(K);
    std::vector<std::vector<double>> cs(K);
    for (std::size_t k = 0; k < K; ++k) {
      const std::vector<double>& c = cos_alpha_v[k];
      order[k].resize(c.size());
      std::iota(order[k].begin(), order[k].end(), std::size_t{0});
      std::stable_sort(order[k].begin(), order[k].end(),
                       [&](std::size_t x, std::size_t y) { return c[x] > c[y]; });
      for (std::size_t j : order[k]) cs[k].push_back(c[j]);
    }
    const std::vector<std::vector<double>> s = lobeIntegral(r_p * r_p, cos_theta_o, b, cs, cells);
    // A cone of zero aperture (A = 0) holds no solid angle: exactly 0, whatever the curvature
    // correction does to t near 1.
    for (std::size_t k = 0; k < K; ++k) {
      out[k].assign(cs[k].size(), 0.0);
      for (std::size_t j = 0; j < cs[k].size(); ++j)
        out[k][order[k][j]] = cs[k][j] >= 1.0 ? 0.0 : s[k][j];
    }
    return out;
  }
  // Mirror limit: the lobe is the delta at wr, so S = DeltaV(wr) = [angle(wr, b) <= alpha_v]
  // (docs/gtso.md §1; the boundary belongs to the cone, with a tie tolerance for rounding in wr.b).
  // A cone of zero aperture (A = 0) holds no solid angle: 0, as for every r_p > 0.
  const Vec3 wo = viewDirection(cos_theta_o);
  const Vec3 wr = {-wo.x, 0.0, wo.z};
  for (std::size_t k = 0; k < K; ++k) {
    const double tr = dot(wr, b[k]);
    for (const double c : cos_alpha_v[k])
      out[k].push_back((c < 1.0 && tr >= c - kMirrorTie) ? 1.0 : 0.0);
  }
  return out;
}

std::vector<double> specularOcclusion(double r_p, double cos_theta_o, const std::vector<Vec3>& b,
                                      const std::vector<double>& cos_alpha_v, int cells) {
  const std::vector<std::vector<double>> s = specularOcclusion(
      r_p, cos_theta_o, b, std::vector<std::vector<double>>(b.size(), cos_alpha_v), cells);
  std::vector<double> out;
  for (const auto& row : s) out.insert(out.end(), row.begin(), row.end());
  return out;
}

}  // namespace gtbake::gtso
