#include "gtso/gtso_tables.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/math_constants.h"
#include "common/progress.h"
#include "common/rng.h"
#include "gtso/gtso_integrator.h"
#include "runtime/gtso_runtime.h"

namespace gtbake::gtso {

namespace {
constexpr double kHalfPi = kPi / 2.0;

// Stress set: half-width of the band around the mirror step, 3 lobe widths of ~2 alpha each,
// plus a floor for the mirror-like lobes; grazing lobes have cos theta_o below kGrazingCos.
constexpr double kStressLobeWidths = 6.0;
constexpr double kStressFloor = 0.02;
constexpr double kGrazingCos = 0.1;
constexpr int kBentNormalsPerLobe = 4;  // 4D error points: bent normals per random lobe

std::array<int, 4> sizes(int dims, int size) {
  return {size, size, size, dims == 4 ? size : 1};
}

GtsoPhysical<double> texelPhysical(int dims, int size, const std::array<int, 4>& i) {
  const std::array<int, 4> n = sizes(dims, size);
  return gtsoTexelPhysical<double>(dims, i.data(), n.data());
}

// The integrator's cone threshold cos(alpha_v) for a texel's half-angle: alpha_v <= 0 is the
// empty cone (cos = 1, S = 0 exactly), alpha_v in (pi/2, pi] the cap wider than a hemisphere that
// continues S beyond A = 1 (gtsoSpanAbove), alpha_v >= pi the whole sphere.
double coneThreshold(double alphaV) {
  return std::cos(std::clamp(alphaV, 0.0, kPi));
}

}  // namespace

const char* axisName(TableAxis axis) {
  switch (axis) {
    case TableAxis::kA:
      return "A";
    case TableAxis::kThetaO:
      return "theta_o";
    case TableAxis::kBeta:
      return "beta";
    case TableAxis::kRoughness:
      return "r_p";
  }
  return "";
}

TableAxis tableAxis(int dims, int axis) {
  static constexpr TableAxis three[3] = {TableAxis::kA, TableAxis::kThetaO, TableAxis::kRoughness};
  static constexpr TableAxis four[4] = {TableAxis::kA, TableAxis::kBeta, TableAxis::kRoughness,
                                        TableAxis::kThetaO};
  if (axis < 0 || axis >= dims || (dims != 3 && dims != 4)) {
    throw Error("internal: no axis " + std::to_string(axis) + " in a " + std::to_string(dims) +
                "D table");
  }
  return dims == 3 ? three[axis] : four[axis];
}

const std::vector<AxisDefinition>& axisDefinitions(int dims) {
  static const auto convert = [](const auto& infos) {
    std::vector<AxisDefinition> out;
    for (const GtsoAxisInfo* i : infos) out.push_back({i->quantity, i->forward, i->alu});
    return out;
  };
  static const std::vector<AxisDefinition> three = convert(kGtso3DAxisInfo);
  static const std::vector<AxisDefinition> four = convert(kGtso4DAxisInfo);
  return dims == 3 ? three : four;
}

void validateTableSize(int size) {
  if (size < 4 || size > 256 || size % 4 != 0) {
    throw Error("--size must be a multiple of 4 in [4, 256] (BC4 blocks are 4x4), got " +
                std::to_string(size));
  }
}

std::size_t Table::index(const std::array<int, 4>& i) const {
  std::size_t flat = 0;
  for (int d = dims - 1; d >= 0; --d) flat = flat * size + i[d];
  return flat;
}

GtsoPoint Table::point(const std::array<int, 4>& i) const {
  const GtsoPhysical<double> p = texelPhysical(dims, size, i);
  return {p.A, p.beta, p.rp, p.thetaO};
}

std::array<int, 3> Table::volume() const {
  return {size, size, dims == 4 ? size * size : size};
}

Table bakeTable(int dims, int size, int cells, Progress* progress,
                const std::vector<std::size_t>* only) {
  validateTableSize(size);
  Table table;
  table.dims = dims;
  table.size = size;
  std::size_t total = 1;
  for (int d = 0; d < dims; ++d) total *= static_cast<std::size_t>(size);
  table.values.assign(total, 0.0);
  // Line (r_p, theta_o): 3D one bent normal b = n (texels y = theta_o), 4D every beta texel.
  const std::size_t lines = only ? only->size() : static_cast<std::size_t>(size) * size;
  tbb::parallel_for(std::size_t{0}, lines, [&](std::size_t job) {
    const std::size_t line = only ? (*only)[job] : job;
    const int r = static_cast<int>(line / size), th = static_cast<int>(line % size);
    std::array<int, 4> i = {0, th, r, 0};
    if (dims == 4) i = {0, 0, r, th};
    const int betas = dims == 3 ? 1 : size;
    std::vector<Vec3> b;
    std::vector<std::vector<double>> cones(betas);
    double theta_o = 0.0, rp = 0.0;
    for (int k = 0; k < betas; ++k) {
      if (dims == 4) i[1] = k;
      i[0] = 0;
      const GtsoPhysical<double> p = texelPhysical(dims, size, i);
      theta_o = p.thetaO;
      rp = p.rp;
      b.push_back(dims == 3 ? Vec3{0.0, 0.0, 1.0} : bentNormal(p.thetaO, p.beta));
      for (int a = 0; a < size; ++a)
        cones[k].push_back(coneThreshold(gtsoTexelAlphaV(a, size, p.beta, p.rp)));
    }
    const std::vector<std::vector<double>> s =
        specularOcclusion(rp, std::cos(theta_o), b, cones, cells);
    for (int k = 0; k < betas; ++k) {
      if (dims == 4) i[1] = k;
      for (int a = 0; a < size; ++a) {
        i[0] = a;
        table.values[table.index(i)] = s[k][a];
      }
    }
    if (progress) progress->add(1);
  });
  return table;
}

double evaluateS(int dims, const GtsoPoint& p, int cells) {
  const double c = std::sqrt(std::clamp(1.0 - p.A, 0.0, 1.0));
  const std::vector<double> cone = {c};
  if (dims == 3)
    return specularOcclusion(p.r_p, std::cos(p.beta), {{0.0, 0.0, 1.0}}, cone, cells)[0];
  return specularOcclusion(p.r_p, std::cos(p.theta_o), {bentNormal(p.theta_o, p.beta)}, cone,
                           cells)[0];
}

ErrorPoints sizedErrorPoints(int lobes, int perLobe) {
  ErrorPoints out;
  out.points.resize(static_cast<std::size_t>(lobes) * perLobe);
  out.exact.resize(out.points.size());
  return out;
}

double stepWindowA(double centre, double half, double v) {
  const double lo = std::clamp(centre - half, 0.0, kHalfPi);
  const double hi = std::clamp(centre + half, 0.0, kHalfPi);
  const double s = std::sin(lo + (hi - lo) * v);
  return s * s;
}

std::vector<float> toFloats(const Table& t) {
  return std::vector<float>(t.values.begin(), t.values.end());
}

EncodedTable floatTable(const Table& t) {
  EncodedTable e;
  e.format = TexelFormat::kFloat32;
  const std::vector<float> f = toFloats(t);
  const std::size_t n = f.size();
  e.bytes.resize(n * 4);
  std::copy(reinterpret_cast<const std::uint8_t*>(f.data()),
            reinterpret_cast<const std::uint8_t*>(f.data()) + n * 4, e.bytes.begin());
  for (std::size_t i = 0; i < n; ++i) {
    const double d = std::abs(f[i] - t.values[i]);
    e.texel_max = std::max(e.texel_max, d);
    e.texel_rms += d * d;
  }
  e.texel_rms = std::sqrt(e.texel_rms / static_cast<double>(n));
  return e;
}

float runtimeLookup(const Table& t, const EncodedTable& e, const GtsoPoint& p) {
  const std::array<int, 3> v = t.volume();
  const GtsoVolume vol{e.format, e.bytes.data(), v[0], v[1], v[2]};
  const std::array<int, 4> n = sizes(t.dims, t.size);
  const float A = static_cast<float>(p.A), cb = static_cast<float>(std::cos(p.beta));
  const float rp = static_cast<float>(p.r_p);
  if (t.dims == 3) return gtso3DLookup(vol, n.data(), A, cb, rp);
  return gtso4DLookup(vol, n.data(), A, cb, rp, static_cast<float>(std::cos(p.theta_o)));
}

const char* pointSetName(PointSet s) {
  return s == PointSet::kUniform ? "uniform" : "stress";
}

namespace {

// The random points of one lobe (r_p, cos theta_o) for one table: points, their bent normals and
// each normal's cones, from the table's own stream (one stream per dims and set).
struct LobePoints {
  std::vector<GtsoPoint> points;
  std::vector<Vec3> b;
  std::vector<std::vector<double>> cones;
  int conesPer = 0;
};

LobePoints drawLobePoints(int dims, PointSet set, const CounterRng& rng, int l, int perLobe,
                          double rp, double cosO) {
  const double theta_o = std::acos(cosO);
  // 3D: one bent normal (n) with perLobe cones; 4D: kBentNormalsPerLobe bent normals with
  // perLobe / kBentNormalsPerLobe cones each (the lobe grid and each normal's t are shared).
  const int normals = dims == 3 ? 1 : kBentNormalsPerLobe;
  LobePoints out;
  out.conesPer = perLobe / normals;
  out.cones.resize(normals);
  for (int k = 0; k < perLobe; ++k) {
    const int group = k / out.conesPer;
    const auto v = rng.uniform4(static_cast<std::uint64_t>(l), 1 + k);
    const auto vb = rng.uniform4(static_cast<std::uint64_t>(l), 1 + perLobe + group);
    GtsoPoint p{v[0], theta_o, rp, theta_o};
    // 4D: cos beta uniform over the bent normals above the horizon (cos beta >= -sin theta_o);
    // the stress set keeps beta <= pi/2, where the mirror step lies inside the A range.
    const double cosBetaMin = set == PointSet::kStress ? 0.0 : -std::sin(theta_o);
    if (dims == 4) p.beta = std::acos(1.0 - (1.0 - cosBetaMin) * vb[0]);
    if (set == PointSet::kStress) {
      // alpha_v uniform over [s - h, s + h] clipped to [0, pi/2] (stepWindowA).
      p.A = stepWindowA(p.beta, kStressLobeWidths * rp * rp + kStressFloor, v[1]);
    }
    out.points.push_back(p);
    if (k % out.conesPer == 0) {
      out.b.push_back(dims == 3 ? Vec3{0.0, 0.0, 1.0} : bentNormal(theta_o, p.beta));
    }
    out.cones[group].push_back(std::sqrt(std::clamp(1.0 - p.A, 0.0, 1.0)));
  }
  return out;
}

CounterRng pointStream(int dims, PointSet set, std::uint64_t seed) {
  return CounterRng(seed, static_cast<std::uint64_t>(dims * 2 + (set == PointSet::kStress)));
}

// The lobe of random lobe l: r_p and cos theta_o (stress: every other lobe grazing, half of
// those squeezed towards the grazing, mirror-like corner).
std::pair<double, double> drawLobe(PointSet set, const CounterRng& rng, int l) {
  const auto u = rng.uniform4(static_cast<std::uint64_t>(l), 0);
  if (set != PointSet::kStress || l % 2 == 0) return {u[0], u[1]};
  // Grazing: lobes l = 1 mod 4 uniform in cos theta_o in [0, 0.1]; lobes l = 3 mod 4 squeezed
  // towards the corner where the largest errors lie (cos theta_o -> 0 with r_p -> 0): both drawn
  // as the square of a uniform, so a quarter of them have cos theta_o < 0.025 and r_p < 0.25.
  if (l % 4 == 1) return {u[0], kGrazingCos * u[1]};
  return {u[0] * u[0], kGrazingCos * u[1] * u[1]};
}

// Integrates the lobe once for the bent normals of every table drawn on it and stores each
// point's exact S.
void integrateLobe(double rp, double cosO, int cells, int l, int perLobe,
                   const std::vector<std::pair<LobePoints*, ErrorPoints*>>& parts) {
  std::vector<Vec3> b;
  std::vector<std::vector<double>> cones;
  for (const auto& [lobe, out] : parts) {
    b.insert(b.end(), lobe->b.begin(), lobe->b.end());
    cones.insert(cones.end(), lobe->cones.begin(), lobe->cones.end());
  }
  const auto s = specularOcclusion(rp, cosO, b, cones, cells);
  std::size_t first = 0;
  for (const auto& [lobe, out] : parts) {
    const std::size_t at = static_cast<std::size_t>(l) * perLobe;
    for (int k = 0; k < perLobe; ++k) {
      out->points[at + k] = lobe->points[k];
      out->exact[at + k] = s[first + k / lobe->conesPer][k % lobe->conesPer];
    }
    first += lobe->b.size();
  }
}

void checkPerLobe(int perLobe) {
  if (perLobe % kBentNormalsPerLobe != 0) throw Error("error points: perLobe must divide by 4");
}

}  // namespace

ErrorPoints makeErrorPoints(int dims, PointSet set, int lobes, int perLobe, std::uint64_t seed,
                            int cells, Progress* progress) {
  checkPerLobe(perLobe);
  const CounterRng rng = pointStream(dims, set, seed);
  ErrorPoints out = sizedErrorPoints(lobes, perLobe);
  tbb::parallel_for(0, lobes, [&](int l) {
    const auto [rp, cosO] = drawLobe(set, rng, l);
    LobePoints lp = drawLobePoints(dims, set, rng, l, perLobe, rp, cosO);
    integrateLobe(rp, cosO, cells, l, perLobe, {{&lp, &out}});
    if (progress) progress->add(1);
  });
  return out;
}

ErrorPointPair makeErrorPointPair(PointSet set, int lobes, int perLobe, std::uint64_t seed,
                                  int cells) {
  checkPerLobe(perLobe);
  const CounterRng rng3 = pointStream(3, set, seed), rng4 = pointStream(4, set, seed);
  ErrorPointPair out{sizedErrorPoints(lobes, perLobe), sizedErrorPoints(lobes, perLobe)};
  tbb::parallel_for(0, lobes, [&](int l) {
    const auto [rp, cosO] = drawLobe(set, rng4, l);
    LobePoints three = drawLobePoints(3, set, rng3, l, perLobe, rp, cosO);
    LobePoints four = drawLobePoints(4, set, rng4, l, perLobe, rp, cosO);
    integrateLobe(rp, cosO, cells, l, perLobe, {{&three, &out.three}, {&four, &out.four}});
  });
  return out;
}

ErrorStats lookupError(const Table& t, const EncodedTable& e, const ErrorPoints& pts) {
  std::vector<double> err(pts.points.size());
  tbb::parallel_for(std::size_t{0}, err.size(), [&](std::size_t i) {
    err[i] = std::abs(runtimeLookup(t, e, pts.points[i]) - pts.exact[i]);
  });
  return errorStats(err, pts);
}

ErrorStats errorStats(const std::vector<double>& err, const ErrorPoints& pts) {
  ErrorStats s;
  for (std::size_t i = 0; i < err.size(); ++i) {
    if (err[i] > s.max) {
      s.max = err[i];
      s.worst = pts.points[i];
    }
    s.rms += err[i] * err[i];
  }
  s.rms = std::sqrt(s.rms / std::max<std::size_t>(err.size(), 1));
  return s;
}

}  // namespace gtbake::gtso
