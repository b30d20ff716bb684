#include "validate_gtso/scene_statistics.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/text_escape.h"
#include "stats/jackknife.h"
#include "sweep/sweep_set.h"

namespace gtbake {

namespace {

using Json = nlohmann::ordered_json;

// Per cluster and pooled RMSE of each method over one roughness's samples `index` (in sample
// order): cluster[method index in `methods`][cluster] and pooled[method index]. One pass over
// just those samples for both.
struct RoughnessRmse {
  std::vector<std::vector<double>> cluster;
  std::vector<double> pooled;
};

RoughnessRmse roughnessRmse(const std::vector<SpecularSample>& samples,
                            const std::vector<std::vector<float>>& values,
                            const std::vector<Method>& methods, const std::vector<int>& cluster_of,
                            std::size_t clusters, const std::vector<std::size_t>& index) {
  std::vector<std::vector<ErrorStats>> e(methods.size(), std::vector<ErrorStats>(clusters));
  std::vector<ErrorStats> pooled(methods.size());
  for (std::size_t i : index) {
    const SpecularSample& s = samples[i];
    const auto c = static_cast<std::size_t>(cluster_of[static_cast<std::size_t>(s.scene)]);
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const float v = values[static_cast<int>(methods[m])][i];
      e[m][c].add(v - s.truth, s.noise_var);
      pooled[m].add(v - s.truth, 0.0);
    }
  }
  RoughnessRmse out;
  out.cluster.resize(methods.size());
  for (std::size_t m = 0; m < methods.size(); ++m) {
    for (const ErrorStats& x : e[m]) out.cluster[m].push_back(x.rmse());
    out.pooled.push_back(pooled[m].rmse());
  }
  return out;
}

Json pairedJson(const PairedTest& t) {
  return {{"scenes", t.scenes},
          {"mean_difference", t.mean_difference},
          {"t", t.t},
          {"p_value", t.p_value},
          {"significant", t.significant}};
}

Json optimumJson(const UOptimum& o) {
  return {{"u", o.u}, {"log10_u", o.log10_u}, {"at_search_bound", o.at_bound}};
}

Json lawJson(const SpecularSweep& sweep, const SceneStatistics& s, int law) {
  const USceneInterval& iv = s.u.interval[law];
  Json per_r = Json::object();
  for (std::size_t j = 0; j < sweep.roughness.size(); ++j) {
    per_r[specularChannelName(sweep.roughness[j])] = optimumJson(s.u.per_roughness[law][j]);
  }
  Json per_scene = Json::object();
  for (std::size_t c = 0; c < s.clusters.size(); ++c) {
    per_scene[s.clusters[c]] = optimumJson(s.u.per_cluster[law][c]);
  }
  return {{"u", std::pow(10.0, iv.log10_u)},
          {"log10_u", iv.log10_u},
          {"log10_u_se", iv.log10_se},
          {"interval", {iv.low, iv.high}},
          {"u_se", iv.u_se},
          {"t_quantile", iv.t},
          {"leave_one_out_log10_u", iv.replicates},
          {"per_roughness", per_r},
          {"per_scene", per_scene},
          {"held_out_rmse", s.u.law.held_out_rmse[law]}};
}

std::string num(const char* format, double v) {
  char text[48];
  std::snprintf(text, sizeof(text), format, v);
  return text;
}

std::string optimumText(const UOptimum& o) {
  return o.at_bound ? "&le; 1e-12 (bound)" : num("%.3g", o.u);
}

}  // namespace

std::string sceneStatisticsHtml(const SpecularSweep& sweep, const SceneStatistics& s) {
  std::ostringstream o;
  o << "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>gtbake validate-gtso: scene "
       "level</title><style>body{font-family:sans-serif;max-width:1100px;margin:1em auto}table{"
       "border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 6px}</style></head><body>"
       "\n<h1>Scene-level statistics</h1>\n<p>"
    << s.clusters.size() << " scenes as units (docs/validate_gtso.md &sect;2, &sect;3). Companion "
    << "of <a href=\"validate_gtso.html\">validate_gtso.html</a>.</p>\n<h2>Rankings</h2>\n<ul>\n";
  for (std::size_t j = 0; j < s.ranking.size(); ++j) {
    o << "<li>r_p " << num("%.2f", sweep.roughness[j]) << ": " << escapeHtml(s.ranking[j].statement)
      << "</li>\n";
  }
  o << "</ul>\n<h2>Cone aperture u</h2>\n<table><tr><th>law</th><th>u</th><th>95% scene-level "
       "interval</th><th>SE log10 u</th>";
  for (double r : sweep.roughness) o << "<th>optimum at r_p " << num("%.2f", r) << "</th>";
  o << "</tr>\n";
  for (int law = 0; law < 2; ++law) {
    const USceneInterval& iv = s.u.interval[law];
    o << "<tr><td>" << (law == 0 ? "u^(alpha^2/2)" : "u^(r_p^2/2)") << "</td><td>"
      << num("%.3g", std::pow(10.0, iv.log10_u)) << "</td><td>[" << num("%.2g", iv.low) << ", "
      << num("%.2g", iv.high) << "]</td><td>" << num("%.2f", iv.log10_se) << "</td>";
    for (const UOptimum& opt : s.u.per_roughness[law]) o << "<td>" << optimumText(opt) << "</td>";
    o << "</tr>\n";
  }
  o << "</table>\n<p>Held-out comparison of the laws: alpha minus perceptual RMSE "
    << num("%+.4f", s.u.law.test.mean_difference) << ", p = " << num("%.3f", s.u.law.test.p_value)
    << "; chosen: " << kLawNames[s.u.law.chosen] << ".</p>\n<h2>Floor (held-out RMSE of a "
    << "regressor on the runtime's inputs)</h2>\n<table><tr>";
  for (double r : sweep.roughness) o << "<th>r_p " << num("%.2f", r) << "</th>";
  o << "</tr>\n<tr>";
  for (double v : s.floor.rmse) o << "<td>" << num("%.4f", v) << "</td>";
  o << "</tr></table>\n</body></html>\n";
  return o.str();
}

std::vector<std::string> sceneClusters(const SpecularSweep& sweep, std::vector<int>& cluster_of,
                                       bool by_type) {
  std::vector<std::string> names;
  for (const SpecularScene& scene : sweep.scenes) {
    const std::string& key = by_type ? scene.typeName() : scene.sceneName();
    const auto it = std::find(names.begin(), names.end(), key);
    cluster_of.push_back(static_cast<int>(it - names.begin()));
    if (it == names.end()) names.push_back(key);
  }
  return names;
}

std::vector<RankingTest> rankingTests(const SpecularSweep& sweep,
                                      const std::vector<SpecularSample>& samples,
                                      const std::vector<std::vector<float>>& values,
                                      const std::vector<Method>& methods,
                                      const std::vector<int>& cluster_of, StageParts& parts) {
  const std::size_t S = static_cast<std::size_t>(
      cluster_of.empty() ? 0 : *std::max_element(cluster_of.begin(), cluster_of.end()) + 1);
  const std::size_t R = sweep.roughness.size();
  std::vector<std::string> names;
  for (Method m : methods) names.push_back(methodName(m));
  return parts.run("scene-level ranking tests", R, [&](Progress& bar) {
    std::vector<std::vector<std::size_t>> index(R);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      index[static_cast<std::size_t>(samples[i].roughness)].push_back(i);
    }
    std::vector<RankingTest> ranking(R);
    tbb::parallel_for(std::size_t{0}, R, [&](std::size_t j) {
      const RoughnessRmse rmse = roughnessRmse(samples, values, methods, cluster_of, S, index[j]);
      ranking[j] = rankingTest(names, rmse.cluster, rmse.pooled);
      bar.add(1);
    });
    return ranking;
  });
}

SceneStatistics sceneStatistics(const SpecularSweep& sweep,
                                const std::vector<SpecularSample>& samples,
                                const std::vector<std::vector<float>>& values,
                                const std::vector<Method>& methods, const ConeSseTable& table,
                                StageParts& parts) {
  SceneStatistics s;
  s.clusters = sceneClusters(sweep, s.cluster_of);
  const std::size_t S = s.clusters.size();
  const std::size_t R = sweep.roughness.size();
  s.u = parts.run("u's scene-level interval", 1, [&](Progress&) { return analyzeU(table); });
  s.ranking = rankingTests(sweep, samples, values, methods, s.cluster_of, parts);
  s.floor = parts.run("SO floor", 1, [&](Progress&) {
    return soFloor(samples, s.cluster_of, S, R, values[static_cast<int>(Method::kS4Float)]);
  });
  s.out_of_plane = outOfPlaneOccluded(samples, values[static_cast<int>(Method::kS4Bc4)],
                                      values[static_cast<int>(Method::kS3Bc4)]);
  return s;
}

nlohmann::ordered_json rankingTestsJson(const SpecularSweep& sweep,
                                        const std::vector<RankingTest>& tests) {
  Json ranking = Json::object();
  for (std::size_t j = 0; j < sweep.roughness.size(); ++j) {
    const RankingTest& r = tests[j];
    Json vs = Json::object();
    for (std::size_t k = 0; k < r.others.size(); ++k) vs[r.others[k]] = pairedJson(r.vs_best[k]);
    ranking[specularChannelName(sweep.roughness[j])] = {{"best", r.best},
                                                        {"tied_with_best", r.tied},
                                                        {"statement", r.statement},
                                                        {"other_minus_best", vs}};
  }
  return {{"method", kPairedTestMethod}, {"by_roughness", ranking}};
}

void addSceneStatisticsJson(const SpecularSweep& sweep, const SceneStatistics& s, Json& json) {
  json["u_scene_interval"] = {
      {"method",
       "delete-one-scene jackknife of log10 u (grid fit, step 0.25 decades, parabolic refinement); "
       "interval log10 u +- t_{0.975, S-1} SE: 95% coverage over scene mixes drawn like this "
       "one, to first order"},
      {"scenes", s.clusters},
      {"alpha", lawJson(sweep, s, 0)},
      {"perceptual", lawJson(sweep, s, 1)}};
  json["u_law"] = {
      {"test", kPairedTestMethod},
      {"compared", "each scene's RMSE at the u fitted without it, alpha minus perceptual"},
      {"alpha_minus_perceptual", pairedJson(s.u.law.test)},
      {"chosen", kLawNames[s.u.law.chosen]}};
  json["ranking_tests"] = rankingTestsJson(sweep, s.ranking);
  Json floor = Json::object();
  for (std::size_t j = 0; j < sweep.roughness.size(); ++j) {
    Json by_bins = Json::object();
    for (std::size_t b = 0; b < s.floor.by_bins.size(); ++b) {
      by_bins[std::to_string(kSoFloorBins[b])] = s.floor.by_bins[b][j];
    }
    floor[specularChannelName(sweep.roughness[j])] = {
        {"rmse", s.floor.rmse[j]},
        {"rmse_noise_corrected", s.floor.rmse_noise_corrected[j]},
        {"rmse_by_bins", by_bins}};
  }
  json["so_floor"] = {
      {"method",
       "leave-one-scene-out RMSE of a binned regressor of path-traced S on (A, b.n, b.wr, n.wr) "
       "at each r_p (equal-count bins per input, fallback to half the bins, then the mean), of S "
       "itself or of S minus the 4D float table (whichever is lower pooled)"},
      {"bins", s.floor.bins},
      {"on_base",
       s.floor.on_base ? "S4_float (the regressor corrects the 4D float table)" : "none"},
      {"by_roughness", floor}};
  Json plane = Json::array();
  for (const OutOfPlaneBin& b : s.out_of_plane) {
    plane.push_back(
        {{"min_deg", b.min_deg},
         {"max_deg", b.max_deg},
         {"open_excluded", b.open_excluded},
         {"S4_bc4",
          {{"count", b.s4.count}, {"rmse", b.s4.rmse()}, {"mean_signed", b.s4.meanSigned()}}},
         {"S3_bc4",
          {{"count", b.s3.count}, {"rmse", b.s3.rmse()}, {"mean_signed", b.s3.meanSigned()}}}});
  }
  json["by_out_of_plane_occluded"] = {{"max_A", kOpenA}, {"bins", plane}};
}

}  // namespace gtbake
