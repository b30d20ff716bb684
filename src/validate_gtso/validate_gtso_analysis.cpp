#include "validate_gtso/validate_gtso_analysis.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>

#include "common/error.h"
#include "common/output_layout.h"
#include "common/progress.h"
#include "validate_gtso/validate_gtso_set.h"

namespace gtbake {

namespace {

namespace fs = std::filesystem;

// What the runtime can use on an estimator's Â and b̂ (docs/validate_gtso.md §6): the shipped BC4
// tables, the cone at the paper's and the shipped u, both floored at A², Lagarde and the two
// trivial baselines. On the ray-traced inputs every method (--u's only when given).
std::vector<Method> scoredMethods(const ValidateGtsoOptions& options) {
  if (!options.input.rayTraced()) {
    return {Method::kS3Bc4,       Method::kS4Bc4,         Method::kConePaperU,
            Method::kConeFittedU, Method::kNone,          Method::kAo,
            Method::kLagarde,     Method::kConeAo2PaperU, Method::kConeAo2FittedU};
  }
  std::vector<Method> methods;
  for (int m = 0; m < kMethodCount; ++m) {
    if (static_cast<Method>(m) == Method::kConeUserU && !(options.u > 0.0)) continue;
    methods.push_back(static_cast<Method>(m));
  }
  return methods;
}

bool scores(const std::vector<Method>& methods, Method m) {
  return std::find(methods.begin(), methods.end(), m) != methods.end();
}

// The error tables of `values` against the samples' truth, or, with `truth` given, against that
// sweep's S at the same scene, roughness and pixel (the unbounded S beside the near-field one).
Tables tabulate(const std::vector<SpecularSample>& samples,
                const std::vector<std::vector<float>>& values, const std::vector<Method>& methods,
                std::size_t scenes, std::size_t roughness, const SpecularSweep* truth = nullptr) {
  const bool formats = scores(methods, Method::kS3Float);
  Tables t;
  t.cell.assign(kMethodCount,
                std::vector<std::vector<ErrorStats>>(scenes, std::vector<ErrorStats>(roughness)));
  t.per_roughness.assign(kMethodCount, std::vector<ErrorStats>(roughness));
  t.overall.assign(kMethodCount, ErrorStats{});
  const auto sample = [&](std::size_t i) {
    SpecularSample s = samples[i];
    if (truth) {
      const SpecularScene& scene = truth->scenes[static_cast<std::size_t>(s.scene)];
      const auto j = static_cast<std::size_t>(s.roughness);
      s.truth = scene.S[j][s.pixel];
      const double d = static_cast<double>(scene.H0[j][s.pixel]) - scene.H1[j][s.pixel];
      s.noise_var = 0.25 * d * d;
    }
    return s;
  };
  // Each cell sums its samples in sample order, whichever thread runs it: the scenes' cells in
  // parallel (a cell is one scene's), beside one pass in sample order for the tables pooled over
  // scenes.
  std::vector<std::vector<std::size_t>> of_scene(scenes);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    of_scene[static_cast<std::size_t>(samples[i].scene)].push_back(i);
  }
  tbb::parallel_invoke(
      [&] {
        tbb::parallel_for(std::size_t{0}, scenes, [&](std::size_t sc) {
          for (std::size_t i : of_scene[sc]) {
            const SpecularSample s = sample(i);
            for (Method method : methods) {
              const int m = static_cast<int>(method);
              t.cell[m][sc][s.roughness].add(values[m][i] - s.truth, s.noise_var);
            }
          }
        });
      },
      [&] {
        for (std::size_t i = 0; i < samples.size(); ++i) {
          const SpecularSample s = sample(i);
          int bin = 0;
          while (bin + 1 < kPlaneBinCount && s.out_of_plane >= kPlaneBins[bin + 1]) ++bin;
          t.plane[0][bin].add(values[static_cast<int>(Method::kS4Bc4)][i] - s.truth, s.noise_var);
          t.plane[1][bin].add(values[static_cast<int>(Method::kS3Bc4)][i] - s.truth, s.noise_var);
          for (int f = 0; f < (formats ? kFormatMethodCount : 0); ++f) {
            const auto [format, floats] = kFormatMethods[f];
            t.vs_float[f].add(
                values[static_cast<int>(format)][i] - values[static_cast<int>(floats)][i], 0.0);
          }
        }
      });
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

// The cone's u on the ray-traced inputs, fitted by the run without --estimator: the u export
// ships, which an engine would feed its estimate.
double shippedU(const ValidateGtsoOptions& options) {
  const fs::path file = options.luts / kValidateGtsoDir / "validate_gtso.json";
  if (!fs::is_regular_file(file)) {
    throw Error("validate-gtso --estimator: no " + file.string() +
                " (run `gtbake validate-gtso` on the ray-traced inputs first: its u is scored)");
  }
  return readValidateGtsoU(file).u;
}

// The sweep and tables read, the samples gathered; on an estimator's inputs A and b replaced.
void readInputs(const ValidateGtsoOptions& options, StageParts& parts, Analysis& a) {
  a.sweep = parts.run("reading the sweep", 1, [&](Progress&) {
    // An estimator's inputs are scored against S_R at its radius (docs/sweep.md, "Near-field
    // truth") unless --truth unbounded.
    const std::optional<double> radius = truthRadius(options.input);
    SpecularSweep sweep = options.sweep_data && options.sweep_data->radius == radius
                              ? *options.sweep_data
                              : readSpecularSweep(options.sweep, radius);
    if (!options.input.rayTraced()) useScreenEstimate(&sweep, options.input);
    return sweep;
  });
  a.samples = parts.run("gathering samples", 1, [&](Progress&) { return gatherSamples(a.sweep); });
}

// The unbounded S of the same sweep, for the comparison kept beside the near-field one: the one
// `gtbake all` read for every estimator (not copied), else read here into *read. Its views must
// be those of the near-field read (the same sweep.json, so a mismatch is internal).
const SpecularSweep& unboundedTruth(const ValidateGtsoOptions& options, const SpecularSweep& near,
                                    std::optional<SpecularSweep>* read) {
  const SpecularSweep* sweep = options.unbounded_sweep_data;
  if (sweep == nullptr || sweep->radius) sweep = &read->emplace(readSpecularSweep(options.sweep));
  bool same = sweep->scenes.size() == near.scenes.size() && sweep->roughness == near.roughness;
  for (std::size_t k = 0; same && k < sweep->scenes.size(); ++k) {
    same = sweep->scenes[k].mask == near.scenes[k].mask;
  }
  if (!same) throw Error("internal: the sweep's unbounded and near-field S differ in their views");
  return *sweep;
}

}  // namespace

Analysis analyse(const ValidateGtsoOptions& options) {
  StageParts parts("validate-gtso", options.progress);
  Analysis a;
  a.estimator = options.input.estimator;
  readInputs(options, parts, a);
  const TablesLookups tables = parts.run(
      "reading the tables", 1, [&](Progress&) { return makeTablesLookups(options.luts); });
  a.tables = tables.info;
  std::vector<int> cluster_of;
  const std::vector<std::string> clusters = sceneClusters(a.sweep, cluster_of);
  ConeConstants cones;
  cones.table_fit = tables.info.u_table_fit;
  cones.user = options.u;
  ConeSseTable table;
  if (a.rayTraced()) {
    table = parts.run("cone SSE table on the log10 u grid", a.samples.size(), [&](Progress& bar) {
      return coneSseTable(a.samples, cluster_of, clusters.size(), a.sweep.roughness.size(), &bar);
    });
    parts.run("u fit (2 laws x 2 subsets)", 4, [&](Progress& bar) {
      a.spec = fitConeU(a.samples, false, &table, &bar);
      a.perceptual = fitConeU(a.samples, true, &table, &bar);
      return 0;
    });
    cones.fitted = a.spec.all.u;
    cones.fitted_perceptual = a.perceptual.all.u;
  } else {
    cones.fitted = a.shipped_u = shippedU(options);
  }
  a.methods = scoredMethods(options);
  a.values = parts.run("every method at every sample", a.samples.size(), [&](Progress& bar) {
    return evaluateMethods(a.samples, tables, cones, a.methods, &bar);
  });
  a.t = parts.run("error tables", 1, [&](Progress&) {
    return tabulate(a.samples, a.values, a.methods, a.sweep.scenes.size(),
                    a.sweep.roughness.size());
  });
  a.ranking = rank(a.t, a.methods, a.sweep.roughness.size());
  if (a.sweep.radius) {
    a.unbounded = parts.run("error tables against the unbounded S", 1, [&](Progress&) {
      std::optional<SpecularSweep> read;
      const SpecularSweep& unbounded = unboundedTruth(options, a.sweep, &read);
      return tabulate(a.samples, a.values, a.methods, a.sweep.scenes.size(),
                      a.sweep.roughness.size(), &unbounded);
    });
  }
  if (a.rayTraced()) {
    a.scene_stats = sceneStatistics(a.sweep, a.samples, a.values, a.methods, table, parts);
  } else {
    a.scene_stats.clusters = clusters;
    a.scene_stats.cluster_of = cluster_of;
    a.scene_stats.ranking =
        rankingTests(a.sweep, a.samples, a.values, a.methods, cluster_of, parts);
  }
  a.part_seconds = parts.seconds();
  return a;
}

}  // namespace gtbake
