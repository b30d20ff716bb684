#include "tune/tune_analysis.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <tuple>

#include "common/error.h"
#include "common/output_set.h"
#include "common/text_format.h"
#include "fit/scene_jackknife.h"
#include "screen_ao/gtao_runtime.h"
#include "screen_ao/screen_ao_set.h"
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

// What scoring a run needs: the sweep (its A replaced by each run's Â), its G-buffer images, the
// scene clusters and each cluster's Σ G².
struct Scoring {
  SweepData* data;
  const SweepImages* images;
  const Grouping* clusters;
  const std::vector<std::vector<long double>>* q;
};

// The score of the estimator's defaults, by estimator: run once and shared by its settings, or
// read from a screen-ao set.
using DefaultScores = std::map<Estimator, GridValueScore>;

// One run's Â ([image]) scored.
GridValueScore scoreEstimates(const Scoring& sc, Estimator estimator,
                              const std::vector<std::vector<float>>& a) {
  useEstimates(sc.data, sc.images->images, a, describe(estimator).name);
  return scoreRun(clusterStatistics(*sc.data, *sc.clusters, *sc.q), sc.clusters->names,
                  sc.data->albedos, profileFitSettings());
}

// Whether a grid is a visibility bitmask's thickness grid, whose values share one pass.
bool isBitmaskThickness(const SettingGrid& grid) {
  return describe(grid.estimator).bitmask != nullptr && grid.key == "thickness";
}

// Every value's estimate of one image in one pass, [grid][value]: the bitmasks' thickness values
// share the samples (visibilityBitmasks; both bitmasks' grids, with the same values, from one pass
// when the group holds both), the runtime pass's values of all of the group's grids share its
// slices, and each radius its horizons and filter weights (gtaoRuntimeRuns); Â alone (tune reads
// no b̂), with the bytes of a run at that value alone.
std::vector<std::vector<AoEstimate>> imageEstimates(
    const GBuffer& g, const std::vector<SettingGrid>& group,
    const std::vector<std::vector<double>>& to_run) {
  const ScreenAoSettings s;
  if (isBitmaskThickness(group[0]) && group.size() == 1) {
    return {visibilityBitmasks(g, s.*describe(group[0].estimator).bitmask, to_run[0],
                               EstimateParts::kAoOnly)};
  }
  if (isBitmaskThickness(group[0])) {
    std::vector<SectorWeights> weights;
    for (const SettingGrid& grid : group) {
      weights.push_back((s.*describe(grid.estimator).bitmask).weights);
    }
    return visibilityBitmasks(g, s.bitmask_uniform, weights, to_run[0], EstimateParts::kAoOnly);
  }
  std::vector<GtaoRuntimeSettings> runs;
  for (std::size_t k = 0; k < group.size(); ++k) {
    if (group[k].estimator != Estimator::kGtaoRuntime) {
      throw Error("internal: tune has no pass for " + std::string(group[k].name()) + "." +
                  group[k].key);
    }
    for (double value : to_run[k]) runs.push_back(settingsAt(group[k], value).runtime);
  }
  std::vector<AoEstimate> all = gtaoRuntimeRuns(g, runs, EstimateParts::kAoOnly);
  std::vector<std::vector<AoEstimate>> out(group.size());
  auto next = std::make_move_iterator(all.begin());
  for (std::size_t k = 0; k < group.size(); ++k) {
    out[k].assign(next, next + static_cast<std::ptrdiff_t>(to_run[k].size()));
    next += static_cast<std::ptrdiff_t>(to_run[k].size());
  }
  return out;
}

// Â of every image at each value of to_run[grid], [grid][value][image], one pass per image for
// the whole group (imageEstimates).
std::vector<std::vector<std::vector<std::vector<float>>>> groupEstimates(
    const SweepImages& images, const std::vector<SettingGrid>& group,
    const std::vector<std::vector<double>>& to_run, Progress& bar) {
  std::vector<std::vector<std::vector<std::vector<float>>>> out(group.size());
  std::size_t runs = 0;
  for (std::size_t k = 0; k < group.size(); ++k) {
    out[k].resize(to_run[k].size());
    runs += to_run[k].size();
  }
  for (const SweepImage& image : images.images) {
    std::vector<std::vector<AoEstimate>> e = imageEstimates(image.gbuffer, group, to_run);
    for (std::size_t w = 0; w < group.size(); ++w) {
      for (std::size_t k = 0; k < to_run[w].size(); ++k) out[w][k].push_back(std::move(e[w][k].a));
    }
    bar.add(runs);
  }
  return out;
}

// The values of a grid that need a run: all but the default when its score is known (or another
// grid of the same pass runs it).
std::vector<double> valuesToRun(const SettingGrid& grid, bool default_known) {
  std::vector<double> to_run;
  for (double value : grid.values) {
    if (value != grid.default_value || !default_known) {
      to_run.push_back(value);
    }
  }
  return to_run;
}

// Scores `values` of one grid from the runs of to_run ([value][image]); a value not run is the
// default, whose score *defaults holds (and keeps once scored).
std::vector<GridValueScore> scoreValues(const Scoring& sc, const SettingGrid& grid,
                                        const std::vector<double>& values,
                                        const std::vector<double>& to_run,
                                        const std::vector<std::vector<std::vector<float>>>& est,
                                        DefaultScores* defaults) {
  std::vector<GridValueScore> scores;
  for (double value : values) {
    const auto run = std::find(to_run.begin(), to_run.end(), value);
    if (run == to_run.end()) {
      scores.push_back(defaults->at(grid.estimator));
    } else {
      scores.push_back(scoreEstimates(sc, grid.estimator, est[run - to_run.begin()]));
    }
    scores.back().value = value;
    if (value == grid.default_value) (*defaults)[grid.estimator] = scores.back();
  }
  return scores;
}

// A part's name: "ESTIMATOR KEY" joined by '+' on the side that differs
// ("gtao-runtime radius+intensity", "bitmask-uniform+bitmask-cosine thickness").
std::string partName(const std::vector<SettingGrid>& group) {
  std::string estimators = group[0].name();
  std::string keys = group[0].key;
  for (std::size_t g = 1; g < group.size(); ++g) {
    if (group[g].estimator != group[0].estimator) estimators += "+" + std::string(group[g].name());
    if (group[g].key != group[0].key) keys += "+" + group[g].key;
  }
  return estimators + " " + keys;
}

// Â computed ahead of the first widening step (docs/tune.md §7), [image] Â by grid (estimator,
// key) and value: taken when widening adds its value, dropped with the pass group otherwise.
using AheadKey = std::tuple<Estimator, std::string, double>;
using Ahead = std::map<AheadKey, std::vector<std::vector<float>>>;

AheadKey aheadKey(const SettingGrid& grid, double value) {
  return {grid.estimator, grid.key, value};
}

// One timed part: to_run[g]'s values of each of the group's grids in one pass per image, each
// grid's `values[g]` scored ([grid][value]) from that pass or, for a value the pass did not run,
// from `ahead` (taken out of it). A value run but not scored is put in `ahead`.
std::vector<std::vector<GridValueScore>> runPart(StageParts& parts, const Scoring& sc,
                                                 const std::vector<SettingGrid>& group,
                                                 const std::vector<std::vector<double>>& values,
                                                 const std::vector<std::vector<double>>& to_run,
                                                 const std::string& suffix, DefaultScores* defaults,
                                                 Ahead* ahead) {
  std::size_t runs = 0;
  for (const std::vector<double>& v : to_run) runs += v.size();
  const std::size_t units = runs * sc.images->images.size();
  return parts.run(partName(group) + suffix, units, [&](Progress& bar) {
    std::vector<std::vector<std::vector<std::vector<float>>>> est(group.size());
    if (runs != 0) est = groupEstimates(*sc.images, group, to_run, bar);  // else all ahead
    std::vector<std::vector<GridValueScore>> scores;
    for (std::size_t g = 0; g < group.size(); ++g) {
      std::vector<double> have = to_run[g];
      for (double value : values[g]) {
        const auto found = ahead->find(aheadKey(group[g], value));
        if (found == ahead->end() || std::count(have.begin(), have.end(), value) != 0) continue;
        have.push_back(value);
        est[g].push_back(std::move(found->second));
        ahead->erase(found);
      }
      scores.push_back(scoreValues(sc, group[g], values[g], have, est[g], defaults));
      for (std::size_t k = 0; k < to_run[g].size(); ++k) {
        if (std::count(values[g].begin(), values[g].end(), to_run[g][k]) == 0) {
          (*ahead)[aheadKey(group[g], to_run[g][k])] = std::move(est[g][k]);
        }
      }
    }
    return scores;
  });
}

// Whether the pass computes a grid's values one widening step beyond its ends (docs/tune.md §7):
// a bitmask's thicknesses share its samples, slices and front angles, so they cost little. The
// runtime pass's two intensities beyond cost 6% of its CPU (measured), more than a widening pass
// is likely to save, and a radius would need its own horizon samples.
bool computesAhead(const SettingGrid& grid) {
  return isBitmaskThickness(grid);
}

// The values the first widening step could add to the grid (widenedEnd at each end that is not
// its limit), when computesAhead.
std::vector<double> aheadValues(const SettingGrid& grid) {
  std::vector<double> out;
  if (!computesAhead(grid)) return out;
  for (const bool upper : {false, true}) {
    if (const std::optional<double> v = widenedEnd(grid, upper)) out.push_back(*v);
  }
  return out;
}

// to_run with the values the first widening step could add computed too (aheadValues), ascending:
// for a bitmask pass, every grid's (the pass runs one list of thicknesses for all its grids).
std::vector<std::vector<double>> withAheadValues(const std::vector<SettingGrid>& group,
                                                 std::vector<std::vector<double>> to_run) {
  const bool one_list = isBitmaskThickness(group[0]);
  std::vector<double> shared;
  for (const SettingGrid& grid : group) {
    for (double v : aheadValues(grid)) shared.push_back(v);
  }
  for (std::size_t g = 0; g < group.size(); ++g) {
    for (double v : one_list ? shared : aheadValues(group[g])) {
      if (std::count(to_run[g].begin(), to_run[g].end(), v) == 0) to_run[g].push_back(v);
    }
    std::sort(to_run[g].begin(), to_run[g].end());
  }
  return to_run;
}

// Whether grids[k] and grids[k + 1] are the two bitmasks' thickness grids with the same values to
// run and the same other settings: then one pass per image serves both (docs/tune.md §7).
bool bitmasksSharePass(const std::vector<SettingGrid>& grids, std::size_t k,
                       const DefaultScores& defaults) {
  if (k + 1 >= grids.size()) return false;
  const SettingGrid& a = grids[k];
  const SettingGrid& b = grids[k + 1];
  const ScreenAoSettings s;
  const bool both =
      a.estimator != b.estimator && describe(a.estimator).bitmask && describe(b.estimator).bitmask;
  return both && a.key == "thickness" && b.key == "thickness" &&
         valuesToRun(a, defaults.count(a.estimator) != 0) ==
             valuesToRun(b, defaults.count(b.estimator) != 0) &&
         sameBitmaskSamples(s.*describe(a.estimator).bitmask, s.*describe(b.estimator).bitmask);
}

// The grids from grids[k] on that one pass per image serves (docs/tune.md §7): both bitmasks'
// thickness grids when they share a pass, every consecutive grid of the runtime pass, else one.
std::size_t passGroupSize(const std::vector<SettingGrid>& grids, std::size_t k,
                          const DefaultScores& defaults) {
  if (isBitmaskThickness(grids[k])) return bitmasksSharePass(grids, k, defaults) ? 2 : 1;
  std::size_t n = 1;
  while (k + n < grids.size() && grids[k + n].estimator == grids[k].estimator) ++n;
  return n;
}

// Runs, scores and widens every grid in order, the grids that share a pass under one part
// (passGroupSize, docs/tune.md §7); a default not yet scored runs once per estimator. With
// `ahead`, the group's pass also computes the values its first widening step could add
// (withAheadValues), and a widening step runs a pass only for the values not computed yet.
void runGrids(StageParts& parts, const Scoring& sc, const std::vector<SettingGrid>& grids,
              bool ahead, DefaultScores* defaults, TuneAnalysis* a) {
  for (std::size_t k = 0; k < grids.size();) {
    const std::size_t n = passGroupSize(grids, k, *defaults);
    const std::vector<SettingGrid> group(grids.begin() + k, grids.begin() + k + n);
    k += n;
    std::vector<std::vector<double>> values, to_run;
    std::set<Estimator> scheduled;  // estimators whose default this pass runs once
    for (const SettingGrid& g : group) {
      values.push_back(g.values);
      const bool known = defaults->count(g.estimator) != 0 || !scheduled.insert(g.estimator).second;
      to_run.push_back(valuesToRun(g, known));
      a->estimator_runs += to_run.back().size();
    }
    Ahead computed;
    const auto scores =
        runPart(parts, sc, group, values, ahead ? withAheadValues(group, to_run) : to_run, "",
                defaults, &computed);
    std::vector<SettingResult> results(group.size());
    for (std::size_t g = 0; g < group.size(); ++g) {
      results[g].grid = group[g];
      results[g].scores = scores[g];
    }
    widenGroup(&results, *a, [&](std::size_t first, std::size_t count, const auto& add) {
      const std::vector<SettingGrid> grids(group.begin() + first, group.begin() + first + count);
      a->estimator_runs += count * add.size();
      // A value not computed ahead for every grid of the step runs for all of them (a shared
      // bitmask pass runs one list of thicknesses).
      std::vector<double> missing;
      for (double value : add) {
        for (const SettingGrid& grid : grids) {
          if (computed.count(aheadKey(grid, value)) == 0) {
            missing.push_back(value);
            break;
          }
        }
      }
      return runPart(parts, sc, grids, std::vector(count, add), std::vector(count, missing),
                     " widened to " + formatNumberList(add), defaults, &computed);
    });
    for (SettingResult& r : results) a->settings.push_back(std::move(r));
  }
}

// Whether the screen-ao set in `dir` ran `estimator` at tune's defaults (its screen_ao.json
// settings), so its Â is the default run's, the same floats (docs/tune.md §7).
bool screenAoHasDefaults(const std::filesystem::path& dir, Estimator e) {
  const char* estimator = describe(e).name;
  const nlohmann::json doc = readOutputSet(dir, "screen_ao").readVerifiedJson("screen_ao.json");
  const nlohmann::json* settings = doc.contains("settings") ? &doc["settings"] : nullptr;
  return settings != nullptr && settings->contains(estimator) && doc.contains("estimators") &&
         doc["estimators"].contains(estimator) &&
         (*settings)[estimator] == nlohmann::json(settingsJson(ScreenAoSettings{}, e));
}

// The defaults' scores of every tuned estimator that the screen-ao set in `dir` holds at tune's
// defaults, from its Â (each image's mask must be the sweep's).
void readDefaults(const Scoring& sc, const std::filesystem::path& dir,
                  const std::filesystem::path& sweep, const std::vector<SettingGrid>& grids,
                  DefaultScores* defaults) {
  for (const SettingGrid& grid : grids) {
    if (defaults->count(grid.estimator) != 0 || !screenAoHasDefaults(dir, grid.estimator)) {
      continue;
    }
    const ScreenEstimateSet set({grid.name(), dir});
    std::vector<std::vector<float>> a;
    for (const SweepImage& image : sc.images->images) {
      ImageEstimate e = set.read(image.name, sweep, false);
      if (e.mask != image.gbuffer.mask) {
        throw Error("tune: the mask of " + e.file + " is not the sweep's '" + image.name + "'");
      }
      a.push_back(std::move(e.A));
    }
    (*defaults)[grid.estimator] = scoreEstimates(sc, grid.estimator, a);
  }
}

}  // namespace

FitSettings profileFitSettings() {
  FitSettings s;
  s.eiv_correction = false;
  s.shape_constrained = true;  // as the profiles (docs/profiles.md §7)
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

namespace {

void findOptima(SettingResult* r, const TuneAnalysis& a) {
  std::vector<double> x;
  for (double v : r->grid.values) x.push_back(axisValue(r->grid, v));
  const ObjectiveCurves paper = objectiveCurves(*r, a.cluster_points, a.albedos.size(), true);
  const ObjectiveCurves profile = objectiveCurves(*r, a.cluster_points, a.albedos.size(), false);
  r->paper = sceneInterval(x, paper.pooled, paper.replicas);
  r->profile = sceneInterval(x, profile.pooled, profile.replicas);
}

// Whether an optimum of either objective, pooled or a replica's, sits at the grid's lower
// (upper = false) or upper end.
bool endReached(const SettingResult& r, bool upper) {
  const double end = axisValue(r.grid, upper ? r.grid.values.back() : r.grid.values.front());
  for (const SceneInterval* o : {&r.paper, &r.profile}) {
    if (o->z == end) return true;
    for (double z : o->replicates) {
      if (z == end) return true;
    }
  }
  return false;
}

// The values the next widening step adds to r's grid (docs/tune.md §3): one beyond each end an
// optimum reaches that is not its limit, within kMaxWidenings steps per end (counted in r).
std::vector<double> nextWidening(SettingResult* r) {
  std::vector<double> add;
  for (const bool upper : {false, true}) {
    int& steps = upper ? r->widened_upper : r->widened_lower;
    const std::optional<double> v = widenedEnd(r->grid, upper);
    if (v && steps < kMaxWidenings && endReached(*r, upper)) {
      add.push_back(*v);
      ++steps;
    }
  }
  return add;
}

void mergeScores(SettingResult* r, std::vector<GridValueScore> added) {
  for (GridValueScore& g : added) r->scores.push_back(std::move(g));
  std::sort(r->scores.begin(), r->scores.end(),
            [](const GridValueScore& x, const GridValueScore& y) { return x.value < y.value; });
  r->grid.values.clear();
  for (const GridValueScore& g : r->scores) r->grid.values.push_back(g.value);
}

}  // namespace

void widenGroup(std::vector<SettingResult>* group, const TuneAnalysis& a, const WidenRun& run) {
  while (true) {
    std::vector<std::vector<double>> adds;
    for (SettingResult& r : *group) {
      findOptima(&r, a);
      adds.push_back(nextWidening(&r));
    }
    const bool shared = group->size() == 2 && adds[0] == adds[1];
    bool any = false;
    for (std::size_t g = 0; g < group->size(); ++g) {
      if (adds[g].empty() || (shared && g == 1)) continue;
      any = true;
      const std::size_t count = shared ? 2 : 1;
      const auto scores = run(g, count, adds[g]);
      for (std::size_t w = 0; w < count; ++w) mergeScores(&(*group)[g + w], scores[w]);
    }
    if (!any) return;
  }
}

OptimumPlace optimumPlace(const SettingResult& r, const SceneInterval& o) {
  OptimumPlace p;
  if (!o.at_bound) return p;
  const bool upper = o.z == axisValue(r.grid, r.grid.values.back());
  p.status = upper ? OptimumStatus::kUpperBound : OptimumStatus::kLowerBound;
  const SettingLimit& limit = upper ? r.grid.upper : r.grid.lower;
  const double end = upper ? r.grid.values.back() : r.grid.values.front();
  p.limit = end == limit.value ? limit
                               : SettingLimit{end, "search end: " + std::to_string(kMaxWidenings) +
                                                       " widening steps used, short of the limit " +
                                                       formatNumber(limit.value, "%g")};
  return p;
}

const char* statusName(OptimumStatus status) {
  switch (status) {
    case OptimumStatus::kInterior:
      return "interior";
    case OptimumStatus::kLowerBound:
      return "lower_bound";
    case OptimumStatus::kUpperBound:
      return "upper_bound";
  }
  return "";
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
                         bool progress, const std::filesystem::path& screen_ao,
                         std::optional<double> truth_radius, bool compute_ahead) {
  StageParts parts("tune", progress);
  SweepData data;
  SweepImages images;
  parts.run("read the sweep", 2, [&](Progress& bar) {
    data = loadSweep(sweep, truth_radius);
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
  a.truth_radius = truth_radius;
  const auto q = clusterTargetSquares(data, clusters);
  const Scoring sc{&data, &images, &clusters, &q};
  DefaultScores defaults;
  if (!screen_ao.empty()) {
    parts.run("read screen-ao's defaults", 1, [&](Progress& bar) {
      readDefaults(sc, screen_ao, sweep, grids, &defaults);
      bar.add(1);
      return 0;
    });
  }
  runGrids(parts, sc, grids, compute_ahead, &defaults, &a);
  a.part_seconds = parts.seconds();
  return a;
}

}  // namespace gtbake
