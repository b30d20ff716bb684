#include "gtso/gtso_tables.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/math_constants.h"
#include "common/progress.h"
#include "common/rng.h"
#include "gtso/gtso_integrator.h"

namespace gtbake::gtso {

namespace {

double betaMax(int dims) {
  return dims == 3 ? kPi / 2.0 : kPi;
}  // 3D: beta = theta_o

std::array<int, 4> unflatten(std::size_t flat, int dims, int size) {
  std::array<int, 4> i = {0, 0, 0, 0};
  for (int d = 0; d < dims; ++d) {
    i[d] = static_cast<int>(flat % size);
    flat /= size;
  }
  return i;
}
}  // namespace

Mapping Mapping::defaults(int dims) {
  Mapping m;
  m.axes = {Axis{"A", 0.0, 1.0}, Axis{"cos_beta", std::cos(betaMax(dims)), 1.0},
            Axis{"r_p", 0.0, 1.0}, Axis{"cos_theta_o", 0.0, 1.0}};
  if (dims == 3) m.axes[1].min = 0.0;  // cos(pi/2) written exactly
  return m;
}

Mapping Mapping::withAlternative(int axis) const {
  Mapping m = *this;
  const double bmax = axes[1].min < -0.5 || axes[1].max > 3.0 ? kPi : kPi / 2.0;
  switch (axis) {
    case 0:
      m.axes[0] = {"cos_alpha_v", 0.0, 1.0};
      break;
    case 1:
      m.axes[1] = {"beta", 0.0, bmax};
      break;
    case 2:
      m.axes[2] = {"alpha", 0.0, 1.0};
      break;
    default:
      m.axes[3] = {"theta_o", 0.0, kPi / 2.0};
      break;
  }
  return m;
}

std::string Mapping::name() const {
  return axes[0].quantity + "," + axes[1].quantity + "," + axes[2].quantity + "," +
         axes[3].quantity;
}

double axisToPhysical(const std::string& q, double v) {
  if (q == "A" || q == "beta" || q == "r_p" || q == "theta_o") return v;
  if (q == "cos_alpha_v") return 1.0 - v * v;
  if (q == "alpha_v") return std::sin(v) * std::sin(v);
  if (q == "cos_beta" || q == "cos_theta_o") return std::acos(std::clamp(v, -1.0, 1.0));
  if (q == "alpha") return std::sqrt(std::max(0.0, v));
  throw Error("unknown GTSO axis quantity '" + q + "'");
}

double physicalToAxis(const std::string& q, double p) {
  if (q == "A" || q == "beta" || q == "r_p" || q == "theta_o") return p;
  if (q == "cos_alpha_v") return std::sqrt(std::max(0.0, 1.0 - p));
  if (q == "alpha_v") return std::asin(std::sqrt(std::clamp(p, 0.0, 1.0)));
  if (q == "cos_beta" || q == "cos_theta_o") return std::cos(p);
  if (q == "alpha") return p * p;
  throw Error("unknown GTSO axis quantity '" + q + "'");
}

std::size_t Table::index(const std::array<int, 4>& i) const {
  std::size_t flat = 0;
  for (int d = dims - 1; d >= 0; --d) flat = flat * size + i[d];
  return flat;
}

GtsoPoint Table::point(const std::array<int, 4>& i) const {
  GtsoPoint p;
  p.A = axisToPhysical(mapping.axes[0].quantity, mapping.axes[0].value(i[0], size));
  p.beta = axisToPhysical(mapping.axes[1].quantity, mapping.axes[1].value(i[1], size));
  p.r_p = axisToPhysical(mapping.axes[2].quantity, mapping.axes[2].value(i[2], size));
  p.thetaO = dims == 3
                 ? p.beta
                 : axisToPhysical(mapping.axes[3].quantity, mapping.axes[3].value(i[3], size));
  return p;
}

double Table::lookup(const GtsoPoint& p) const {
  const double params[4] = {p.A, p.beta, p.r_p, p.thetaO};
  int i0[4] = {0, 0, 0, 0};
  double f[4] = {0, 0, 0, 0};
  for (int d = 0; d < dims; ++d) {
    const Axis& a = mapping.axes[d];
    const double q = physicalToAxis(a.quantity, params[d]);
    const double x = std::clamp((q - a.min) / (a.max - a.min), 0.0, 1.0) * (size - 1);
    i0[d] = std::min(static_cast<int>(x), size - 2);
    f[d] = x - i0[d];
  }
  double sum = 0.0;
  for (int corner = 0; corner < (1 << dims); ++corner) {
    std::array<int, 4> i = {0, 0, 0, 0};
    double w = 1.0;
    for (int d = 0; d < dims; ++d) {
      const int bit = (corner >> d) & 1;
      i[d] = i0[d] + bit;
      w *= bit ? f[d] : 1.0 - f[d];
    }
    sum += w * values[index(i)];
  }
  return sum;
}

Table bakeTable(int dims, const Mapping& mapping, int size, int cells, Progress* progress) {
  Table table;
  table.dims = dims;
  table.size = size;
  table.mapping = mapping;
  std::size_t total = 1;
  for (int d = 0; d < dims; ++d) total *= static_cast<std::size_t>(size);
  table.values.assign(total, 0.0);
  std::vector<double> cosAlphaV(size);
  for (int a = 0; a < size; ++a) {
    const double A = axisToPhysical(mapping.axes[0].quantity, mapping.axes[0].value(a, size));
    cosAlphaV[a] = std::sqrt(std::clamp(1.0 - A, 0.0, 1.0));
  }
  // 3D line (r_p, beta): theta_o = beta, b = n. 4D line (r_p, theta_o): every beta.
  const std::size_t lines = static_cast<std::size_t>(size) * size;
  tbb::parallel_for(std::size_t{0}, lines, [&](std::size_t line) {
    const int outer = static_cast<int>(line / size), inner = static_cast<int>(line % size);
    std::array<int, 4> i = {0, 0, outer, 0};
    std::vector<Vec3> b;
    double thetaO = 0.0;
    if (dims == 3) {
      i[1] = inner;
      thetaO = table.point(i).beta;
      b.push_back({0.0, 0.0, 1.0});
    } else {
      i[3] = inner;
      thetaO = table.point(i).thetaO;
      for (int k = 0; k < size; ++k) {
        i[1] = k;
        b.push_back(bentNormal(thetaO, table.point(i).beta));
      }
    }
    const double r_p = table.point(i).r_p;
    const std::vector<double> s = specularOcclusion(r_p, std::cos(thetaO), b, cosAlphaV, cells);
    for (std::size_t k = 0; k < b.size(); ++k) {
      if (dims == 4) i[1] = static_cast<int>(k);
      for (int a = 0; a < size; ++a) {
        i[0] = a;
        table.values[table.index(i)] = s[k * size + a];
      }
    }
    if (progress) progress->add(1);
  });
  return table;
}

double evaluateS(int dims, const GtsoPoint& p, int cells) {
  const double c = std::sqrt(std::clamp(1.0 - p.A, 0.0, 1.0));
  if (dims == 3)
    return specularOcclusion(p.r_p, std::cos(p.beta), {{0.0, 0.0, 1.0}}, {c}, cells)[0];
  return specularOcclusion(p.r_p, std::cos(p.thetaO), {bentNormal(p.thetaO, p.beta)}, {c},
                           cells)[0];
}

ErrorStats interpolationError(const Table& table, int count, int cells, std::uint64_t seed,
                              double rpMin) {
  const CounterRng rng(seed, static_cast<std::uint64_t>(table.dims));
  std::vector<double> err(count);
  const double cosBetaMin = std::cos(betaMax(table.dims));
  tbb::parallel_for(0, count, [&](int n) {
    const auto u = rng.uniform4(static_cast<std::uint64_t>(n), 0);
    GtsoPoint p;
    p.A = u[0];
    p.beta = std::acos(cosBetaMin + (1.0 - cosBetaMin) * u[1]);
    p.r_p = rpMin + (1.0 - rpMin) * u[2];
    p.thetaO = table.dims == 3 ? p.beta : std::acos(static_cast<double>(u[3]));
    err[n] = std::abs(table.lookup(p) - evaluateS(table.dims, p, cells));
  });
  ErrorStats s;
  for (double e : err) {
    s.max = std::max(s.max, e);
    s.rms += e * e;
  }
  s.rms = std::sqrt(s.rms / std::max(count, 1));
  return s;
}

std::vector<float> toLayout(const Table& table, const std::array<int, 4>& layout) {
  std::vector<float> out(table.values.size());
  for (std::size_t flat = 0; flat < out.size(); ++flat) {
    const std::array<int, 4> f = unflatten(flat, table.dims, table.size);
    std::array<int, 4> logical = {0, 0, 0, 0};
    for (int d = 0; d < table.dims; ++d) logical[layout[d]] = f[d];
    out[flat] = static_cast<float>(table.values[table.index(logical)]);
  }
  return out;
}

ErrorStats bc4ProxyError(const std::vector<float>& v, int dims, int size) {
  std::size_t slices = 1;
  for (int d = 2; d < dims; ++d) slices *= static_cast<std::size_t>(size);
  const std::size_t plane = static_cast<std::size_t>(size) * size;
  ErrorStats s;
  for (std::size_t sl = 0; sl < slices; ++sl) {
    for (int by = 0; by < size; by += 4) {
      for (int bx = 0; bx < size; bx += 4) {
        double lo = 1.0, hi = 0.0;
        for (int y = by; y < std::min(by + 4, size); ++y)
          for (int x = bx; x < std::min(bx + 4, size); ++x) {
            lo = std::min(lo, static_cast<double>(v[sl * plane + y * size + x]));
            hi = std::max(hi, static_cast<double>(v[sl * plane + y * size + x]));
          }
        const double e0 = std::floor(std::clamp(lo, 0.0, 1.0) * 255.0) / 255.0;
        const double e1 = std::ceil(std::clamp(hi, 0.0, 1.0) * 255.0) / 255.0;
        for (int y = by; y < std::min(by + 4, size); ++y)
          for (int x = bx; x < std::min(bx + 4, size); ++x) {
            const double val = v[sl * plane + y * size + x];
            const double k = e1 > e0 ? std::round((val - e0) / (e1 - e0) * 7.0) : 0.0;
            const double e = std::abs(e0 + std::clamp(k, 0.0, 7.0) / 7.0 * (e1 - e0) - val);
            s.max = std::max(s.max, e);
            s.rms += e * e;
          }
      }
    }
  }
  s.rms = std::sqrt(s.rms / static_cast<double>(v.size()));
  return s;
}

}  // namespace gtbake::gtso
