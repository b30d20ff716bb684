#include "tune/tune_analysis.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "common/error.h"
#include "common/text_format.h"
#include "fit/scene_jackknife.h"
#include "fit/screen_estimate.h"
#include "screen_ao/gtao_runtime.h"
#include "screen_ao/visibility_bitmask.h"

namespace gtbake {

namespace {

double rmse(double sse, std::size_t points, std::size_t albedos) {
  return std::sqrt(sse / (static_cast<double>(points) * static_cast<double>(albedos)));
}

double sum(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s;
}

// The sweep's views and its G-buffer images are the same list (both follow sweep.json).
void requireSameViews(const SweepData& data, const SweepImages& images) {
  if (images.images.size() != data.scenes.size()) {
    throw Error("tune: the sweep's EXRs and its G-buffer list different images");
  }
  for (std::size_t v = 0; v < data.scenes.size(); ++v) {
    const GBuffer& g = images.images[v].gbuffer;
    const auto unmasked = static_cast<std::size_t>(std::count(g.mask.begin(), g.mask.end(), 1));
    if (images.images[v].name != data.scenes[v].name ||
        unmasked != data.scenes[v].end - data.scenes[v].begin) {
      throw Error("tune: the G-buffer of '" + images.images[v].name +
                  "' does not match the sweep's points");
    }
  }
}

// Every value's estimate of one image in one pass: the bitmasks' thickness values share the
// samples (visibilityBitmasks), the runtime pass's values its slices, horizons and filter weights
// (gtaoRuntimeRuns); Â alone (tune reads no b̂), with the bytes of a run at that value alone.
std::vector<AoEstimate> runImage(const GBuffer& g, const SettingGrid& grid,
                                 const std::vector<double>& values) {
  if (grid.key == "thickness") {
    const ScreenAoSettings s;
    const BitmaskSettings& b =
        grid.estimator == "bitmask-uniform" ? s.bitmask_uniform : s.bitmask_cosine;
    return visibilityBitmasks(g, b, values, EstimateParts::kAoOnly);
  }
  if (grid.estimator != "gtao-runtime") {
    throw Error("internal: tune has no pass for " + grid.estimator + "." + grid.key);
  }
  std::vector<GtaoRuntimeSettings> runs;
  for (double value : values) runs.push_back(settingsAt(grid, value).runtime);
  return gtaoRuntimeRuns(g, runs, EstimateParts::kAoOnly);
}

// Â of every image at each value ([value][image]).
std::vector<std::vector<std::vector<float>>> runValues(const SweepImages& images,
                                                       const SettingGrid& grid,
                                                       const std::vector<double>& values,
                                                       Progress& bar) {
  std::vector<std::vector<std::vector<float>>> out(values.size());
  for (const SweepImage& image : images.images) {
    std::vector<AoEstimate> e = runImage(image.gbuffer, grid, values);
    for (std::size_t k = 0; k < values.size(); ++k) out[k].push_back(std::move(e[k].a));
    bar.add(values.size());
  }
  return out;
}

// The values of a grid that need a run: all but the default when *at_default holds its score.
std::vector<double> valuesToRun(const SettingGrid& grid,
                                const std::optional<GridValueScore>& at_default) {
  std::vector<double> to_run;
  for (double value : grid.values) {
    if (value != grid.default_value || !at_default.has_value()) to_run.push_back(value);
  }
  return to_run;
}

// Scores every value of one setting's grid from the runs of to_run ([value][image]; the default
// value's run shared by the estimator's settings through *at_default).
std::vector<GridValueScore> scoreGrid(SweepData* data, const SweepImages& images,
                                      const Grouping& clusters,
                                      const std::vector<std::vector<long double>>& q,
                                      const SettingGrid& grid, const std::vector<double>& to_run,
                                      const std::vector<std::vector<std::vector<float>>>& estimates,
                                      std::optional<GridValueScore>* at_default) {
  std::vector<GridValueScore> scores;
  for (double value : grid.values) {
    const auto run = std::find(to_run.begin(), to_run.end(), value);
    if (run == to_run.end()) {
      scores.push_back(**at_default);
    } else {
      useEstimates(data, images.images, estimates[run - to_run.begin()], grid.estimator);
      scores.push_back(scoreRun(clusterStatistics(*data, clusters, q), clusters.names,
                                data->albedos, profileFitSettings()));
    }
    scores.back().value = value;
    if (value == grid.default_value) *at_default = scores.back();
  }
  return scores;
}

// Whether grids[k] and grids[k + 1] are the two bitmasks' thickness grids with the same values to
// run (to_run, the first's) and the same other settings: then one pass per image serves both
// (docs/tune.md §7). The second is another estimator, so its default is run too.
bool bitmasksSharePass(const std::vector<SettingGrid>& grids, std::size_t k,
                       const std::vector<double>& to_run) {
  if (k + 1 >= grids.size()) return false;
  const SettingGrid& a = grids[k];
  const SettingGrid& b = grids[k + 1];
  const ScreenAoSettings s;
  const bool both = (a.estimator == "bitmask-uniform" && b.estimator == "bitmask-cosine") ||
                    (a.estimator == "bitmask-cosine" && b.estimator == "bitmask-uniform");
  return both && a.key == "thickness" && b.key == "thickness" && to_run == b.values &&
         sameBitmaskSamples(s.bitmask_uniform, s.bitmask_cosine);
}

SectorWeights weightsOf(const std::string& estimator) {
  return estimator == "bitmask-uniform" ? SectorWeights::kUniform : SectorWeights::kCosine;
}

// Both bitmasks' thickness grids (bitmasksSharePass) from one pass per image: each image's Â of
// both weightings at every value of to_run, then each grid scored as runGrid would.
std::vector<SettingResult> runBitmaskPair(SweepData* data, const SweepImages& images,
                                          const Grouping& clusters,
                                          const std::vector<std::vector<long double>>& q,
                                          const SettingGrid& first, const SettingGrid& second,
                                          const std::vector<double>& to_run,
                                          std::optional<GridValueScore>* at_default,
                                          Progress& bar) {
  const ScreenAoSettings defaults;
  const std::vector<SettingGrid> grids = {first, second};
  std::vector<std::vector<std::vector<std::vector<float>>>> out(
      2, std::vector<std::vector<std::vector<float>>>(to_run.size()));  // [grid][value][image]
  for (const SweepImage& image : images.images) {
    auto e = visibilityBitmasks(image.gbuffer, defaults.bitmask_uniform,
                                {weightsOf(first.estimator), weightsOf(second.estimator)}, to_run,
                                EstimateParts::kAoOnly);
    for (std::size_t w = 0; w < 2; ++w) {
      for (std::size_t k = 0; k < to_run.size(); ++k) out[w][k].push_back(std::move(e[w][k].a));
    }
    bar.add(2 * to_run.size());
  }
  std::vector<SettingResult> results(2);
  for (std::size_t w = 0; w < 2; ++w) {
    if (w == 1) at_default->reset();  // another estimator
    results[w].grid = grids[w];
    results[w].scores = scoreGrid(data, images, clusters, q, grids[w], to_run, out[w], at_default);
  }
  return results;
}

// Scores every value of one setting's grid (the default value's run shared by the estimator's
// settings through *at_default).
std::vector<GridValueScore> runGrid(SweepData* data, const SweepImages& images,
                                    const Grouping& clusters,
                                    const std::vector<std::vector<long double>>& q,
                                    const SettingGrid& grid,
                                    std::optional<GridValueScore>* at_default, Progress& bar) {
  const std::vector<double> to_run = valuesToRun(grid, *at_default);
  const auto estimates = runValues(images, grid, to_run, bar);
  return scoreGrid(data, images, clusters, q, grid, to_run, estimates, at_default);
}

void findOptima(SettingResult* r, const TuneAnalysis& a) {
  std::vector<double> x;
  for (double v : r->grid.values) x.push_back(axisValue(r->grid, v));
  const ObjectiveCurves paper = objectiveCurves(*r, a.cluster_points, a.albedos.size(), true);
  const ObjectiveCurves profile = objectiveCurves(*r, a.cluster_points, a.albedos.size(), false);
  r->paper = sceneInterval(x, paper.pooled, paper.replicas);
  r->profile = sceneInterval(x, profile.pooled, profile.replicas);
}

// Runs and scores every grid in order, each under its own part of `parts`; the two bitmasks'
// thickness grids under one part when they share a pass (bitmasksSharePass, docs/tune.md §7).
void runGrids(StageParts& parts, SweepData* data, const SweepImages& images,
              const Grouping& clusters, const std::vector<std::vector<long double>>& q,
              const std::vector<SettingGrid>& grids, TuneAnalysis* a) {
  std::optional<GridValueScore> at_default;
  for (std::size_t k = 0; k < grids.size(); ++k) {
    if (k == 0 || grids[k].estimator != grids[k - 1].estimator) at_default.reset();
    const std::vector<double> to_run = valuesToRun(grids[k], at_default);
    const std::size_t units = to_run.size() * images.images.size();
    std::vector<SettingResult> results(1);
    if (bitmasksSharePass(grids, k, to_run)) {
      results = parts.run(grids[k].estimator + "+" + grids[k + 1].estimator + " thickness",
                          2 * units, [&](Progress& bar) {
                            return runBitmaskPair(data, images, clusters, q, grids[k], grids[k + 1],
                                                  to_run, &at_default, bar);
                          });
      ++k;
    } else {
      results[0].grid = grids[k];
      results[0].scores =
          parts.run(grids[k].estimator + " " + grids[k].key, units, [&](Progress& bar) {
            return runGrid(data, images, clusters, q, grids[k], &at_default, bar);
          });
    }
    for (SettingResult& r : results) {
      a->estimator_runs += to_run.size();
      findOptima(&r, *a);
      a->settings.push_back(std::move(r));
    }
  }
}

}  // namespace

FitSettings profileFitSettings() {
  FitSettings s;
  s.eiv_correction = false;
  return s;
}

GridValueScore scoreRun(const std::vector<ClusterStatistics>& stats,
                        const std::vector<std::string>& names, const std::vector<double>& albedos,
                        const FitSettings& settings) {
  const std::size_t S = stats.size();
  GridValueScore out;
  const ClusterStatistics total = sumClusters(stats);
  out.refit = refitCoefficients(total, albedos, settings);
  out.paper_sse.resize(S);
  out.profile_sse.resize(S);
  out.held_out_sse.resize(S);
  out.profile_replica_sse.resize(S);
  tbb::parallel_for(std::size_t{0}, S, [&](std::size_t s) {
    out.paper_sse[s] = sumSquaredError(stats[s], albedos, kPaperCoeffs);
    out.profile_sse[s] = sumSquaredError(stats[s], albedos, out.refit);
    std::vector<bool> include(S, true);
    include[s] = false;
    const ClusterStatistics without = sumClusters(stats, include);
    MultiBounceCoeffs k{};
    try {
      k = refitCoefficients(without, albedos, settings);
    } catch (const Error& e) {
      throw TuneNotApplicable(
          "tune: the profile refit without scene '" + names[s] +
          "' is not determined by the other scenes (" + e.what() +
          "), so there is no scene-level interval; tune needs more varied scenes");
    }
    out.held_out_sse[s] = sumSquaredError(stats[s], albedos, k);
    out.profile_replica_sse[s] = sumSquaredError(without, albedos, k);
  });
  const std::size_t n = total.sums.points, M = albedos.size();
  out.paper_rmse = rmse(sum(out.paper_sse), n, M);
  out.profile_rmse = rmse(sum(out.profile_sse), n, M);
  out.held_out_rmse = rmse(sum(out.held_out_sse), n, M);
  return out;
}

ObjectiveCurves objectiveCurves(const SettingResult& r, const std::vector<std::size_t>& points,
                                std::size_t albedos, bool paper) {
  ObjectiveCurves c;
  std::size_t n = 0;
  for (std::size_t p : points) n += p;
  c.replicas.assign(points.size(), {});
  for (const GridValueScore& g : r.scores) {
    c.pooled.push_back(paper ? g.paper_rmse : g.profile_rmse);
    const double total = paper ? sum(g.paper_sse) : 0.0;
    for (std::size_t s = 0; s < points.size(); ++s) {
      // Without scene s: the paper's constants stay, the profile is refitted without it.
      const double sse = paper ? total - g.paper_sse[s] : g.profile_replica_sse[s];
      c.replicas[s].push_back(rmse(sse, n - points[s], albedos));
    }
  }
  return c;
}

void useEstimates(SweepData* data, const std::vector<SweepImage>& images,
                  const std::vector<std::vector<float>>& estimates, const std::string& estimator) {
  for (std::size_t v = 0; v < images.size(); ++v) {
    const GBuffer& g = images[v].gbuffer;
    std::size_t i = data->scenes[v].begin;
    for (std::size_t p = 0; p < g.pixels(); ++p) {
      if (g.mask[p] == 0) continue;
      const std::optional<float> a = clampedEstimate(estimates[v][p]);
      if (!a) {
        throw Error("tune: " + estimator + " gave A = " + formatNumber(estimates[v][p], "%.9g") +
                    " outside [0, 1] on '" + images[v].name + "'");
      }
      data->full.A[i++] = *a;
    }
  }
}

TuneAnalysis analyzeTune(const std::filesystem::path& sweep, const std::vector<SettingGrid>& grids,
                         bool progress) {
  StageParts parts("tune", progress);
  SweepData data;
  SweepImages images;
  parts.run("read the sweep", 2, [&](Progress& bar) {
    data = loadSweep(sweep);
    bar.add(1);
    images = readSweepImages(sweep);
    bar.add(1);
    return 0;
  });
  requireSameViews(data, images);
  const Grouping clusters = groupByScene(data);
  if (clusters.names.size() < kMinJackknifeScenes) {
    throw TuneNotApplicable("tune: the sweep has " + std::to_string(clusters.names.size()) +
                            " scene(s); the scene-level interval needs at least " +
                            std::to_string(kMinJackknifeScenes));
  }
  TuneAnalysis a;
  a.clusters = clusters.names;
  a.cluster_points.assign(clusters.names.size(), 0);
  for (std::size_t v = 0; v < data.scenes.size(); ++v) {
    a.cluster_points[clusters.of[v]] += data.scenes[v].end - data.scenes[v].begin;
  }
  a.points = data.points();
  a.albedos = data.albedos;
  a.sweep_version = images.sweep_version;
  const auto q = clusterTargetSquares(data, clusters);
  runGrids(parts, &data, images, clusters, q, grids, &a);
  a.part_seconds = parts.seconds();
  return a;
}

}  // namespace gtbake
