#include "validate_gtso/validate_gtso_analysis.h"

#include <algorithm>

#include "common/progress.h"

namespace gtbake {

namespace {

std::vector<Method> scoredMethods(bool user_u) {
  std::vector<Method> methods;
  for (int m = 0; m < kMethodCount; ++m) {
    if (static_cast<Method>(m) == Method::kConeUserU && !user_u) continue;
    methods.push_back(static_cast<Method>(m));
  }
  return methods;
}

Tables tabulate(const std::vector<SpecularSample>& samples,
                const std::vector<std::vector<float>>& values, std::size_t scenes,
                std::size_t roughness) {
  Tables t;
  t.cell.assign(kMethodCount,
                std::vector<std::vector<ErrorStats>>(scenes, std::vector<ErrorStats>(roughness)));
  t.per_roughness.assign(kMethodCount, std::vector<ErrorStats>(roughness));
  t.overall.assign(kMethodCount, ErrorStats{});
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const SpecularSample& s = samples[i];
    for (int m = 0; m < kMethodCount; ++m) {
      t.cell[m][s.scene][s.roughness].add(values[m][i] - s.truth, s.noise_var);
    }
    int bin = 0;
    while (bin + 1 < kPlaneBinCount && s.out_of_plane >= kPlaneBins[bin + 1]) ++bin;
    t.plane[0][bin].add(values[static_cast<int>(Method::kS4Bc4)][i] - s.truth, s.noise_var);
    t.plane[1][bin].add(values[static_cast<int>(Method::kS3Bc4)][i] - s.truth, s.noise_var);
    for (int f = 0; f < kFormatMethodCount; ++f) {
      const auto [format, floats] = kFormatMethods[f];
      t.vs_float[f].add(values[static_cast<int>(format)][i] - values[static_cast<int>(floats)][i],
                        0.0);
    }
  }
  for (int m = 0; m < kMethodCount; ++m) {
    for (std::size_t sc = 0; sc < scenes; ++sc) {
      for (std::size_t j = 0; j < roughness; ++j) {
        t.per_roughness[m][j].merge(t.cell[m][sc][j]);
        t.overall[m].merge(t.cell[m][sc][j]);
      }
    }
  }
  return t;
}

// Methods by RMSE at each roughness, best first (ties by name, so the order is deterministic).
std::vector<std::vector<Method>> rank(const Tables& t, const std::vector<Method>& methods,
                                      std::size_t roughness) {
  std::vector<std::vector<Method>> ranking(roughness, methods);
  for (std::size_t j = 0; j < roughness; ++j) {
    std::stable_sort(ranking[j].begin(), ranking[j].end(), [&](Method a, Method b) {
      return t.per_roughness[static_cast<int>(a)][j].rmse() <
             t.per_roughness[static_cast<int>(b)][j].rmse();
    });
  }
  return ranking;
}

}  // namespace

Analysis analyse(const ValidateGtsoOptions& options) {
  StageParts parts("validate-gtso", options.progress);
  Analysis a;
  a.sweep = parts.run("reading the sweep", 1,
                      [&](Progress&) { return readSpecularSweep(options.sweep); });
  const TablesLookups tables = parts.run(
      "reading the tables", 1, [&](Progress&) { return makeTablesLookups(options.luts); });
  a.tables = tables.info;
  a.samples = parts.run("gathering samples", 1, [&](Progress&) { return gatherSamples(a.sweep); });
  std::vector<int> cluster_of;
  const std::size_t clusters = sceneClusters(a.sweep, cluster_of).size();
  const ConeSseTable table =
      parts.run("cone SSE table on the log10 u grid", a.samples.size(), [&](Progress& bar) {
        return coneSseTable(a.samples, cluster_of, clusters, a.sweep.roughness.size(), &bar);
      });
  parts.run("u fit (2 laws x 2 subsets)", 4, [&](Progress& bar) {
    a.spec = fitConeU(a.samples, false, &table, &bar);
    a.perceptual = fitConeU(a.samples, true, &table, &bar);
    return 0;
  });
  ConeConstants cones;
  cones.table_fit = tables.info.u_table_fit;
  cones.fitted = a.spec.all.u;
  cones.fitted_perceptual = a.perceptual.all.u;
  cones.user = options.u;
  a.values = parts.run("every method at every sample", a.samples.size(), [&](Progress& bar) {
    return evaluateMethods(a.samples, tables, cones, &bar);
  });
  a.methods = scoredMethods(options.u > 0.0);
  a.t = parts.run("error tables", 1, [&](Progress&) {
    return tabulate(a.samples, a.values, a.sweep.scenes.size(), a.sweep.roughness.size());
  });
  a.ranking = rank(a.t, a.methods, a.sweep.roughness.size());
  a.scene_stats = sceneStatistics(a.sweep, a.samples, a.values, a.methods, table, parts);
  a.part_seconds = parts.seconds();
  return a;
}

}  // namespace gtbake
