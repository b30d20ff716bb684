#include "validate_gtso/u_scene_interval.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "stats/jackknife.h"
#include "validate_gtso/cone_u_fit.h"

namespace gtbake {

namespace {

// Sample indices per (cluster, roughness), in sample order.
std::vector<std::vector<std::vector<std::size_t>>> groups(
    const std::vector<SpecularSample>& samples, const std::vector<int>& cluster_of,
    std::size_t clusters, std::size_t roughness) {
  std::vector<std::vector<std::vector<std::size_t>>> g(
      clusters, std::vector<std::vector<std::size_t>>(roughness));
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const SpecularSample& s = samples[i];
    if (s.r_p <= 0.0f) continue;
    g[static_cast<std::size_t>(cluster_of[static_cast<std::size_t>(s.scene)])]
     [static_cast<std::size_t>(s.roughness)]
         .push_back(i);
  }
  return g;
}

// Σ over the clusters with include[c] and the roughness values with use[j] of the table.
std::vector<double> summed(const std::vector<std::vector<std::vector<double>>>& sse,
                           const std::vector<char>& include, const std::vector<char>& use) {
  std::vector<double> out(sse.front().front().size(), 0.0);
  for (std::size_t c = 0; c < sse.size(); ++c) {
    if (include[c] == 0) continue;
    for (std::size_t j = 0; j < sse[c].size(); ++j) {
      if (use[j] == 0) continue;
      for (std::size_t k = 0; k < out.size(); ++k) out[k] += sse[c][j][k];
    }
  }
  return out;
}

UOptimum optimum(const ConeSseTable& t, int law, const std::vector<char>& include,
                 const std::vector<char>& use) {
  UOptimum o;
  o.log10_u = gridArgmin(t.log10_u, summed(t.sse[law], include, use), &o.at_bound);
  o.u = std::pow(10.0, o.log10_u);
  return o;
}

// SSE of cluster c over every roughness at log10 u = z (linear interpolation in the table).
double clusterSseAt(const ConeSseTable& t, int law, std::size_t c, double z) {
  const std::vector<char> only(t.sse[law].size(), 0);
  std::vector<char> include = only;
  include[c] = 1;
  const std::vector<double> y =
      summed(t.sse[law], include, std::vector<char>(t.count.front().size(), 1));
  const double f = (z - t.log10_u.front()) / kUGridStep;
  const auto k = static_cast<std::size_t>(std::clamp(std::floor(f), 0.0, double(y.size() - 2)));
  const double w = std::clamp(f - static_cast<double>(k), 0.0, 1.0);
  return (1.0 - w) * y[k] + w * y[k + 1];
}

USceneInterval interval(const ConeSseTable& t, int law) {
  const std::size_t S = t.sse[law].size();
  const std::vector<char> all_r(t.count.front().size(), 1);
  USceneInterval out;
  out.log10_u = optimum(t, law, std::vector<char>(S, 1), all_r).log10_u;
  for (std::size_t c = 0; c < S; ++c) {
    std::vector<char> include(S, 1);
    include[c] = 0;
    out.replicates.push_back(optimum(t, law, include, all_r).log10_u);
  }
  out.log10_se = jackknifeSe(out.replicates);
  out.t = studentT975(S - 1);
  out.low = std::pow(10.0, out.log10_u - out.t * out.log10_se);
  out.high = std::min(1.0, std::pow(10.0, out.log10_u + out.t * out.log10_se));
  out.u_se = std::pow(10.0, out.log10_u) * std::log(10.0) * out.log10_se;
  return out;
}

}  // namespace

ConeSseTable coneSseTable(const std::vector<SpecularSample>& samples,
                          const std::vector<int>& cluster_of, std::size_t clusters,
                          std::size_t roughness, Progress* progress) {
  ConeSseTable t;
  for (double z = kLog10UMin; z < kLog10UMax; z += kUGridStep) t.log10_u.push_back(z);
  t.log10_u.push_back(kLog10UMax);
  const auto g = groups(samples, cluster_of, clusters, roughness);
  t.count.assign(clusters, std::vector<std::size_t>(roughness, 0));
  for (std::size_t c = 0; c < clusters; ++c) {
    for (std::size_t j = 0; j < roughness; ++j) t.count[c][j] = g[c][j].size();
  }
  const std::size_t K = t.log10_u.size();
  for (int law = 0; law < 2; ++law) {
    t.sse[law].assign(clusters,
                      std::vector<std::vector<double>>(roughness, std::vector<double>(K)));
  }
  // One task per (cluster, roughness): each sample is read once and scored at every grid point
  // of both laws; each grid point's sum still runs in sample order (the same bits as one pass per
  // grid point).
  tbb::parallel_for(std::size_t{0}, clusters * roughness, [&](std::size_t task) {
    const std::size_t j = task % roughness, c = task / roughness;
    if (g[c][j].empty()) return;
    const double r_p = samples[g[c][j].front()].r_p;
    std::vector<ConeAperture> apertures;
    for (int law = 0; law < 2; ++law) {
      for (std::size_t k = 0; k < K; ++k) {
        apertures.push_back(coneAperture(std::pow(10.0, t.log10_u[k]), law == 1 ? r_p : r_p * r_p));
      }
    }
    std::vector<double> sse(2 * K, 0.0);
    for (std::size_t i : g[c][j]) {
      const ConeInput x = coneInput(samples[i]);
      for (std::size_t k = 0; k < 2 * K; ++k) {
        const double e = coneAt(x, apertures[k]) - x.truth;
        sse[k] += e * e;
      }
    }
    for (int law = 0; law < 2; ++law) {
      std::copy(sse.begin() + law * K, sse.begin() + (law + 1) * K, t.sse[law][c][j].begin());
    }
    if (progress) progress->add(g[c][j].size());
  });
  return t;
}

double gridArgmin(const std::vector<double>& x, const std::vector<double>& y, bool* at_bound) {
  const auto k = static_cast<std::size_t>(std::min_element(y.begin(), y.end()) - y.begin());
  *at_bound = k == 0 || k + 1 == y.size();
  if (*at_bound) return x[k];
  const double a = y[k - 1], b = y[k], c = y[k + 1];
  const double curvature = a - 2.0 * b + c;
  if (!(curvature > 0.0)) return x[k];
  const double h = x[k + 1] - x[k];
  return x[k] + 0.5 * h * (a - c) / curvature;
}

UAnalysis analyzeU(const ConeSseTable& t) {
  const std::size_t S = t.count.size();
  if (S < kMinJackknifeScenes) {
    throw Error("u scene interval: needs at least " + std::to_string(kMinJackknifeScenes) +
                " scenes, got " + std::to_string(S));
  }
  const std::size_t R = t.count.front().size();
  UAnalysis a;
  a.clusters = S;
  for (int law = 0; law < 2; ++law) {
    a.interval[law] = interval(t, law);
    for (std::size_t j = 0; j < R; ++j) {
      std::vector<char> use(R, 0);
      use[j] = 1;
      a.per_roughness[law].push_back(optimum(t, law, std::vector<char>(S, 1), use));
    }
    for (std::size_t c = 0; c < S; ++c) {
      std::vector<char> only(S, 0);
      only[c] = 1;
      a.per_cluster[law].push_back(optimum(t, law, only, std::vector<char>(R, 1)));
      std::size_t n = 0;
      for (std::size_t j = 0; j < R; ++j) n += t.count[c][j];
      const double sse = clusterSseAt(t, law, c, a.interval[law].replicates[c]);
      a.law.held_out_rmse[law].push_back(std::sqrt(sse / static_cast<double>(n)));
    }
  }
  a.law.test = pairedSignFlip(a.law.held_out_rmse[0], a.law.held_out_rmse[1]);
  a.law.chosen = a.law.test.mean_difference <= 0.0 ? 0 : 1;
  return a;
}

}  // namespace gtbake
