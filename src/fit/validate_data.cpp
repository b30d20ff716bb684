#include "fit/validate_data.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/input_limits.h"
#include "common/output_set.h"

namespace gtbake {

namespace {

// The bin of A (A = 1 in the last).
std::size_t binOf(double A) {
  const auto b = static_cast<long>(std::floor(A * kValidateBins));
  return static_cast<std::size_t>(std::clamp(b, 0L, static_cast<long>(kValidateBins) - 1));
}

// One view's sums, in point order, in long double.
ViewSums viewSums(const SweepData& data, const SweepScene& s) {
  const std::size_t albedos = data.albedos.size();
  std::vector<std::array<long double, kPowerSums>> power(kValidateBins);
  std::vector<std::vector<std::array<long double, kGSums>>> g(
      kValidateBins, std::vector<std::array<long double, kGSums>>(albedos));
  for (std::size_t i = s.begin; i < s.end; ++i) {
    const long double A = data.full.A[i];
    const std::size_t b = binOf(data.full.A[i]);
    long double Ak = 1.0L;
    for (int k = 0; k < kPowerSums; ++k, Ak *= A) power[b][k] += Ak;
    for (std::size_t j = 0; j < albedos; ++j) {
      const long double G = data.full.G[j][i];
      std::array<long double, kGSums>& t = g[b][j];
      t[0] += G;
      t[1] += G * G;
      t[2] += G * A;
      t[3] += G * A * A;
      t[4] += G * A * A * A;
    }
  }
  ViewSums out;
  out.name = s.name;
  out.scene = s.cluster.empty() ? s.name : s.cluster;
  out.type = s.type.empty() ? s.name : s.type;
  out.bins.resize(kValidateBins);
  for (int b = 0; b < kValidateBins; ++b) {
    for (int k = 0; k < kPowerSums; ++k) out.bins[b].power[k] = static_cast<double>(power[b][k]);
    out.bins[b].albedo.resize(albedos);
    for (std::size_t j = 0; j < albedos; ++j) {
      for (int q = 0; q < kGSums; ++q) out.bins[b].albedo[j][q] = static_cast<double>(g[b][j][q]);
    }
  }
  return out;
}

// The coefficients of a cubic on A^1..A^3: (c, −b, a).
std::array<double, 4> monomials(const Cubic& t) {
  return {0.0, t[2], -t[1], t[0]};
}

// Σ_{m,n} d_m d_n Σ A^(m+n) over bins [first, last).
double quadraticForm(const ViewSums& v, std::size_t first, std::size_t last,
                     const std::array<double, 4>& d) {
  double sum = 0.0;
  for (std::size_t b = first; b < last; ++b) {
    for (int m = 1; m < 4; ++m) {
      for (int n = 1; n < 4; ++n) sum += d[m] * d[n] * v.bins[b].power[m + n];
    }
  }
  return sum;
}

}  // namespace

std::size_t ValidateData::points() const {
  double n = 0.0;
  for (const ViewSums& v : views) n += pointCount(v, 0, kValidateBins);
  return static_cast<std::size_t>(n);
}

Grouping groupViews(const std::vector<ViewSums>& views, std::string ViewSums::*field) {
  Grouping g;
  for (const ViewSums& v : views) {
    const auto found = std::find(g.names.begin(), g.names.end(), v.*field);
    g.of.push_back(static_cast<std::size_t>(found - g.names.begin()));
    if (found == g.names.end()) g.names.push_back(v.*field);
  }
  return g;
}

double pointCount(const ViewSums& v, std::size_t first, std::size_t last) {
  double n = 0.0;
  for (std::size_t b = first; b < last; ++b) n += v.bins[b].power[0];
  return n;
}

double sumSquaredDifference(const ViewSums& v, std::size_t first, std::size_t last, const Cubic& p,
                            const Cubic& q) {
  const std::array<double, 4> mp = monomials(p), mq = monomials(q);
  std::array<double, 4> d{};
  for (int m = 0; m < 4; ++m) d[m] = mp[m] - mq[m];
  return std::max(quadraticForm(v, first, last, d), 0.0);
}

double sumSquaredError(const ViewSums& v, std::size_t first, std::size_t last, std::size_t albedo,
                       const Cubic& p) {
  const std::array<double, 4> m = monomials(p);
  double sum = quadraticForm(v, first, last, m);
  for (std::size_t b = first; b < last; ++b) {
    const std::array<double, kGSums>& g = v.bins[b].albedo[albedo];
    sum += g[1] - 2.0 * (m[1] * g[2] + m[2] * g[3] + m[3] * g[4]);
  }
  return std::max(sum, 0.0);
}

ValidateData validateDataOf(const FitAnalysis& a) {
  ValidateData out;
  out.source = a.data.dir.string();
  out.spp = a.data.spp;
  out.bounces = a.data.bounces;
  out.albedos = a.data.albedos;
  out.settings = a.fit.settings;
  out.input = a.input.rayTraced() ? "ray-traced" : a.input.estimator;
  out.refit = a.fit.linear.coeffs;
  out.mc_se = a.fit.linear.se;
  out.mc_covariance = a.fit.linear.mc_covariance;
  out.scene_jackknife = a.jackknife;
  out.type_jackknife = a.type_jackknife;
  for (const FloorRow& row : a.floor.per_albedo) out.floor_per_albedo.push_back(row.floor);
  out.floor_rmse = a.floor.rmse;
  out.views.resize(a.data.scenes.size());
  tbb::parallel_for(std::size_t{0}, out.views.size(), [&](std::size_t v) {
    out.views[v] = viewSums(a.data, a.data.scenes[v]);
    out.views[v].weight_share = a.view_weights[v].share;
    out.views[v].floor_rmse = a.floor.per_scene[v].floor;
  });
  return out;
}

ValidateData readValidateData(const std::filesystem::path& dir) {
  const OutputManifest manifest = readOutputSet(dir, "fit");
  const std::string name = kValidateDataFile;
  if (manifest.find(name) == nullptr) {
    throw Error((dir / manifestFileName("fit")).string() +
                " lists no validate_data.json (a fit from an older gtbake: run gtbake fit again, "
                "or validate --sweep DIR)");
  }
  const std::string where = (dir / name).string();
  ValidateData data = parseValidateData(parseJsonText(manifest.readVerified(name), where), where);
  data.source = where;
  return data;
}

}  // namespace gtbake
