#include <cmath>
#include <cstdio>

#include "common/text_format.h"
#include "fit/multibounce_coeffs.h"
#include "gtbake_version.h"
#include "tune/tune_outputs.h"

namespace gtbake {

namespace {

using Json = nlohmann::ordered_json;

Json coeffsJson(const MultiBounceCoeffs& k) {
  Json j = Json::object();
  for (int i = 0; i < 6; ++i) j[kCoeffNames[i]] = k[i];
  return j;
}

double clusterRmse(double sse, std::size_t points, std::size_t albedos) {
  return std::sqrt(sse / (static_cast<double>(points) * static_cast<double>(albedos)));
}

Json gridValueJson(const GridValueScore& g, const TuneAnalysis& a) {
  Json clusters = Json::object();
  const std::size_t M = a.albedos.size();
  for (std::size_t c = 0; c < a.clusters.size(); ++c) {
    clusters[a.clusters[c]] = {
        {"paper", clusterRmse(g.paper_sse[c], a.cluster_points[c], M)},
        {"profile", clusterRmse(g.profile_sse[c], a.cluster_points[c], M)},
        {"profile_held_out", clusterRmse(g.held_out_sse[c], a.cluster_points[c], M)}};
  }
  return {{"value", g.value},
          {"rmse",
           {{"paper", g.paper_rmse},
            {"profile", g.profile_rmse},
            {"profile_held_out", g.held_out_rmse}}},
          {"refit", coeffsJson(g.refit)},
          {"clusters", clusters}};
}

Json optimumJson(const SettingResult& r, bool paper) {
  const SceneInterval& o = paper ? r.paper : r.profile;
  const auto objective = [&](const GridValueScore& g) {
    return paper ? g.paper_rmse : g.profile_rmse;
  };
  std::size_t best = 0;
  for (std::size_t k = 1; k < r.scores.size(); ++k) {
    if (objective(r.scores[k]) < objective(r.scores[best])) best = k;
  }
  const OptimumPlace place = optimumPlace(r, o);
  Json limit = nullptr;
  if (place.status != OptimumStatus::kInterior) {
    limit = {{"value", place.limit.value}, {"reason", place.limit.reason}};
  }
  return {{"value", optimumValue(r, o.z)},
          {"axis_value", o.z},
          {"status", statusName(place.status)},
          {"limit", limit},
          {"at_bound", o.at_bound},
          {"se", o.se},
          {"t_quantile", o.t},
          {"interval", {optimumValue(r, o.low), optimumValue(r, o.high)}},
          {"interval_axis", {o.low, o.high}},
          {"interval_clipped", o.interval_clipped},
          {"replicates", o.replicates},
          {"replicates_at_bound", o.replicates_at_bound},
          {"flat_range", {r.grid.values[o.flat_first], r.grid.values[o.flat_last]}},
          {"grid_best",
           {{"value", r.scores[best].value},
            {"paper", r.scores[best].paper_rmse},
            {"profile", r.scores[best].profile_rmse},
            {"profile_held_out", r.scores[best].held_out_rmse}}},
          {"refit", coeffsJson(r.scores[best].refit)}};
}

Json settingJson(const SettingResult& r, const TuneAnalysis& a) {
  Json grid = Json::array();
  for (const GridValueScore& g : r.scores) grid.push_back(gridValueJson(g, a));
  return {{"axis", r.grid.log_axis ? "log10" : "linear"},
          {"default", r.grid.default_value},
          {"values", r.grid.values},
          {"widened", {{"lower", r.widened_lower}, {"upper", r.widened_upper}}},
          {"grid", grid},
          {"optimum", {{"paper", optimumJson(r, true)}, {"profile", optimumJson(r, false)}}}};
}

}  // namespace

double optimumValue(const SettingResult& r, double z) {
  return valueOnAxis(r.grid, z);
}

std::string optimumSummary(const SettingResult& r, const SceneInterval& o) {
  const OptimumPlace place = optimumPlace(r, o);
  const std::string value = formatNumber(optimumValue(r, o.z), "%.3g");
  if (place.status != OptimumStatus::kInterior) {  // a bound: how many replicas are there too
    return std::string(place.status == OptimumStatus::kLowerBound ? "<= " : ">= ") + value +
           " bound (" + std::to_string(o.replicates_at_bound) + "/" +
           std::to_string(o.replicates.size()) + " replicas)";
  }
  return value + " [" + formatNumber(optimumValue(r, o.low), "%.3g") + ", " +
         formatNumber(optimumValue(r, o.high), "%.3g") + "]" +
         (o.interval_clipped ? " clipped" : "");
}

Json tuneSettingsJson(const std::vector<SettingGrid>& grids, const std::string& sweep) {
  Json g = Json::array();
  std::vector<std::string> estimators;
  for (const SettingGrid& s : grids) {
    if (estimators.empty() || estimators.back() != s.name()) estimators.push_back(s.name());
    g.push_back({{"estimator", s.name()},
                 {"key", s.key},
                 {"axis", s.log_axis ? "log10" : "linear"},
                 {"default", s.default_value},
                 {"values", s.values},
                 {"limits",
                  {{"lower", {{"value", s.lower.value}, {"reason", s.lower.reason}}},
                   {"upper", {{"value", s.upper.value}, {"reason", s.upper.reason}}}}}});
  }
  return {{"sweep", sweep},
          {"estimators", estimators},
          {"grids", g},
          {"one_at_a_time", true},
          {"max_widenings", kMaxWidenings},
          {"weighting", "pixel"},
          {"profile_fit",
           {{"eiv_correction", false}, {"constrain_open", false}, {"shape_constrained", true}}},
          {"flat_fraction", kFlatFraction}};
}

Json tuneJson(const TuneAnalysis& a, const std::vector<SettingGrid>& grids,
              const TuneProvenance& provenance) {
  Json results = Json::object();
  for (const SettingResult& r : a.settings) {
    results[r.grid.name()][r.grid.key] = settingJson(r, a);
  }
  Json seconds = Json::object();
  for (const auto& [part, s] : a.part_seconds) seconds[part] = s;
  Json clusters = Json::array();
  for (std::size_t c = 0; c < a.clusters.size(); ++c) {
    clusters.push_back({{"scene", a.clusters[c]}, {"points", a.cluster_points[c]}});
  }
  Json j;
  j["gtbake_version"] = GTBAKE_VERSION;
  j["settings"] = tuneSettingsJson(grids, provenance.sweep);
  j["sweep"] = {{"points", a.points}, {"albedos", a.albedos}, {"clusters", clusters}};
  // What every value was scored against (docs/tune.md §1).
  j["truth"] = a.truth_radius ? nlohmann::json{{"kind", "near-field"}, {"radius", *a.truth_radius}}
                              : nlohmann::json{{"kind", "unbounded"}, {"radius", nullptr}};
  j["results"] = results;
  j["provenance"] = {{"gtbake_version", GTBAKE_VERSION},
                     {"sweep", provenance.sweep},
                     {"sweep_gtbake_version", a.sweep_version},
                     {"estimator_runs", a.estimator_runs},
                     {"seconds", seconds},
                     {"total_seconds", provenance.seconds}};
  return j;
}

void printTuneSummary(const TuneAnalysis& a) {
  std::printf("%-16s %-18s %7s | %-34s | %-34s | %s\n", "estimator", "setting", "default",
              "paper: optimum [95% interval]", "profile: optimum [95% interval]",
              "profile within 5%");
  for (const SettingResult& r : a.settings) {
    std::string cells[2];
    int k = 0;
    for (const SceneInterval* o : {&r.paper, &r.profile}) cells[k++] = optimumSummary(r, *o);
    char flat[64];
    std::snprintf(flat, sizeof flat, "%.3g-%.3g", r.grid.values[r.profile.flat_first],
                  r.grid.values[r.profile.flat_last]);
    std::printf("%-16s %-18s %7.3g | %-34s | %-34s | %s\n", r.grid.name(), r.grid.key.c_str(),
                r.grid.default_value, cells[0].c_str(), cells[1].c_str(), flat);
  }
  std::fflush(stdout);
}

}  // namespace gtbake
