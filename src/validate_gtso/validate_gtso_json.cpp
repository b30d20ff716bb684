// validate_gtso.json from analyse()'s result (docs/validate_gtso.md §5): formatting only.
#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/output_layout.h"
#include "common/output_set.h"
#include "gtbake_version.h"
#include "gtso/cone_intersection.h"
#include "sweep/sweep_set.h"
#include "validate_gtso/method_jackknife.h"
#include "validate_gtso/scene_statistics.h"
#include "validate_gtso/validate_gtso_outputs.h"

namespace gtbake {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

Json statsJson(const ErrorStats& e) {
  Json j;
  j["count"] = e.count;
  j["rmse"] = e.rmse();
  j["rmse_noise_corrected"] = e.rmseNoiseCorrected();
  j["mean_signed"] = e.meanSigned();
  j["max_abs"] = e.max_abs;
  return j;
}

Json fitJson(const UFit& f) {
  Json j;
  j["u"] = f.u;
  // The u range whose pooled RMSE is within 5% of the optimum: a flatness measure of the
  // objective, not a confidence interval (u_scene_interval is that).
  j["rmse_within_5pct"] = {f.low, f.high};
  j["rmse_within_5pct_open"] = {f.low_open, f.high_open};
  j["rmse"] = f.rmse;
  j["rmse_u_0.01"] = f.rmse_paper;
  j["rmse_u_0.244"] = f.rmse_uludag;
  j["samples"] = f.count;
  return j;
}

// validate_gtso.json /sweep: what was read.
Json sweepJson(const ValidateGtsoOptions& options, const fs::path& out, const Analysis& a) {
  const SpecularSweep& sweep = a.sweep;
  std::vector<int> cluster_of;
  return {{"dir", relativePath(options.sweep, out)},
          {"spp", sweep.spp},
          {"specular_spp", sweep.specular_spp},
          {"roughness", sweep.roughness},
          {"views", sweep.scenes.size()},
          {"scenes", sceneClusters(sweep, cluster_of).size()},
          {"pixels", a.samples.size() / sweep.roughness.size()}};
}

// validate_gtso.json: inputs, conventions and the u fits.
void addSettingsJson(const ValidateGtsoOptions& options, const fs::path& out, const Analysis& a,
                     Json& json) {
  json["gtbake_version"] = GTBAKE_VERSION;
  json["sweep"] = sweepJson(options, out, a);
  json["tables"] = {{"dir", relativePath(options.luts, out)}, {"bc4_source", a.tables.bc4_source},
                    {"r16_source", a.tables.r16_source},      {"r8_source", a.tables.r8_source},
                    {"layout_3d", a.tables.layout_3d},        {"layout_4d", a.tables.layout_4d},
                    {"u_table_fit", a.tables.u_table_fit}};
  json["roughness_convention"] = "perceptual roughness r_p; GGX alpha = r_p^2";
  json["lagarde_roughness"] =
      "r = alpha = r_p^2: Filament computeSpecularAO(shading_NoV, ao, pixel.roughness) with "
      "pixel.roughness = perceptualRoughnessToRoughness(perceptualRoughness); HDRP "
      "GetSpecularOcclusionFromAmbientOcclusion(NdotV, ao, PerceptualSmoothnessToRoughness(...))";
  const USceneInterval& u_scene = a.scene_stats.u.interval[0];  // scene-level, alpha law
  json["u"] = a.spec.all.u;
  json["u_interval"] = {u_scene.low, u_scene.high};  // scene-level, u_scene_interval/alpha
  json["u_se"] = u_scene.u_se;
  json["u_fit"] = {{"objective",
                    "least squares of S_cone(u) - path-traced S over every unmasked pixel and "
                    "roughness r_p > 0 (log10 u: scan, golden section, parabolas to 1e-5 decades); "
                    "rmse_within_5pct: flatness, not a CI"},
                   {"alpha",
                    {{"convention", "cos(alpha_s) = u^(alpha^2/2), alpha = r_p^2"},
                     {"all", fitJson(a.spec.all)},
                     {"r_p_ge_0.3", fitJson(a.spec.rp_ge_0_3)}}},
                   {"perceptual",
                    {{"convention", "cos(alpha_s) = u^(r_p^2/2)"},
                     {"all", fitJson(a.perceptual.all)},
                     {"r_p_ge_0.3", fitJson(a.perceptual.rp_ge_0_3)}}}};
}

// validate_gtso.json: every method overall and per roughness, the noise and the rankings.
void addMethodsJson(const Analysis& a, Json& json) {
  const Tables& t = a.t;
  Json method_list = Json::object();
  for (Method m : a.methods) method_list[methodName(m)] = methodDescription(m);
  json["methods"] = method_list;
  Json overall = Json::object();
  for (Method m : a.methods) overall[methodName(m)] = statsJson(t.overall[static_cast<int>(m)]);
  json["overall"] = overall;
  Json by_roughness = Json::object();
  Json noise = Json::object();
  Json ranking_json = Json::object();
  Json best = Json::object();
  for (std::size_t j = 0; j < a.sweep.roughness.size(); ++j) {
    const std::string key = specularChannelName(a.sweep.roughness[j]);
    Json row = Json::object();
    for (Method m : a.methods)
      row[methodName(m)] = statsJson(t.per_roughness[static_cast<int>(m)][j]);
    by_roughness[key] = row;
    const ErrorStats& e = t.per_roughness[static_cast<int>(Method::kNone)][j];
    noise[key] = {{"mean_variance", e.count ? e.noise / e.count : 0.0},
                  {"rms_standard_error", e.count ? std::sqrt(e.noise / e.count) : 0.0}};
    Json order = Json::array();
    for (Method m : a.ranking[j]) order.push_back(methodName(m));
    ranking_json[key] = order;
    best[key] = methodName(a.ranking[j][0]);
  }
  json["per_roughness"] = by_roughness;
  json["truth_noise"] = noise;
  json["ranking"] = ranking_json;
  json["best"] = best;
}

// validate_gtso.json: the out-of-plane bins, each format against float, and every scene.
// validate_gtso.json scene_jackknife, type_jackknife: every method's RMSE with its delete-one-scene
// and delete-one-type SE (method_jackknife.h).
void addMethodJackknifeJson(const Analysis& a, Json& json) {
  std::vector<std::string> scored;
  std::vector<std::vector<std::vector<ErrorStats>>> scored_cells;
  for (Method m : a.methods) {
    scored.push_back(methodName(m));
    scored_cells.push_back(a.t.cell[static_cast<int>(m)]);
  }
  json["scene_jackknife"] = methodJackknifeJson(a.sweep, "scene", scored, scored_cells);
  json["type_jackknife"] = methodJackknifeJson(a.sweep, "type", scored, scored_cells);
}

void addBreakdownJson(const Analysis& a, Json& json) {
  const Tables& t = a.t;
  Json plane = Json::array();
  for (int b = 0; b < kPlaneBinCount; ++b) {
    plane.push_back({{"min_deg", kPlaneBins[b]},
                     {"max_deg", kPlaneBins[b + 1]},
                     {"S4_bc4", statsJson(t.plane[0][b])},
                     {"S3_bc4", statsJson(t.plane[1][b])}});
  }
  json["by_out_of_plane"] = plane;
  Json vs_float = Json::object();
  for (int f = 0; f < (a.rayTraced() ? kFormatMethodCount : 0); ++f) {
    const ErrorStats& e = t.vs_float[f];
    vs_float[methodName(kFormatMethods[f].first)] = {
        {"against", methodName(kFormatMethods[f].second)},
        {"count", e.count},
        {"rms", e.rmse()},
        {"mean_signed", e.meanSigned()},
        {"max_abs", e.max_abs}};
  }
  if (a.rayTraced()) json["format_vs_float"] = vs_float;
  Json scenes = Json::object();
  for (std::size_t sc = 0; sc < a.sweep.scenes.size(); ++sc) {
    Json scene = Json::object();
    for (std::size_t j = 0; j < a.sweep.roughness.size(); ++j) {
      Json row = Json::object();
      for (Method m : a.methods) row[methodName(m)] = statsJson(t.cell[static_cast<int>(m)][sc][j]);
      scene[specularChannelName(a.sweep.roughness[j])] = row;
    }
    scenes[a.sweep.scenes[sc].name] = scene;
  }
  json["views"] = scenes;
}

// validate_gtso.json on an estimator's inputs: what replaced A and b, and the u values scored.
void addEstimatorSettingsJson(const ValidateGtsoOptions& options, const fs::path& out,
                              const Analysis& a, Json& json) {
  json["gtbake_version"] = GTBAKE_VERSION;
  json["input"] = {
      {"estimator", a.estimator},
      {"screen_ao", relativePath(options.input.screen_ao, out)},
      {"replaces",
       "A and the bent normal b at every pixel by the estimator's A and BN channels (world space) "
       "as screen-ao stored them: for gtao-runtime the RGBA8 values the runtime reads"}};
  json["sweep"] = sweepJson(options, out, a);
  json["tables"] = {{"dir", relativePath(options.luts, out)},
                    {"bc4_source", a.tables.bc4_source},
                    {"layout_3d", a.tables.layout_3d},
                    {"layout_4d", a.tables.layout_4d}};
  json["roughness_convention"] = "perceptual roughness r_p; GGX alpha = r_p^2";
  json["u"] = {
      {"paper", gtso::kPaperU},
      {"fitted", a.shipped_u},
      {"fitted_source", relativePath(options.luts / kValidateGtsoDir / "validate_gtso.json", out)},
      {"convention", "cos(alpha_s) = u^(alpha^2/2), alpha = r_p^2"}};
  json["ao2_floor"] =
      "cone_ao2_*: max(S_cone, A^2), one reading of the runtime pass's 'ao^2 grazing-angle "
      "compensation' (docs/validate_gtso.md section 1)";
}

// Which truth the errors are against and, beside a near-field one, the same methods' errors
// against the unbounded S, named as such (docs/validate_gtso.md §6).
void addTruthJson(const Analysis& a, Json& json) {
  json["truth"] = a.sweep.radius ? Json{{"kind", "near-field"}, {"radius", *a.sweep.radius}}
                                 : Json{{"kind", "unbounded"}, {"radius", nullptr}};
  if (!a.unbounded) return;
  Json overall = Json::object();
  for (Method m : a.methods) {
    overall[methodName(m)] = statsJson(a.unbounded->overall[static_cast<int>(m)]);
  }
  Json by_roughness = Json::object();
  for (std::size_t j = 0; j < a.sweep.roughness.size(); ++j) {
    Json row = Json::object();
    for (Method m : a.methods) {
      row[methodName(m)] = statsJson(a.unbounded->per_roughness[static_cast<int>(m)][j]);
    }
    by_roughness[specularChannelName(a.sweep.roughness[j])] = row;
  }
  json["unbounded_truth"] = {
      {"note", "the same values against the sweep's unbounded S, which no screen-space input sees"},
      {"overall", overall},
      {"per_roughness", by_roughness}};
}

}  // namespace

nlohmann::ordered_json validateGtsoJson(const ValidateGtsoOptions& options, const fs::path& out,
                                        const Analysis& a, double seconds) {
  Json json;
  if (a.rayTraced()) {
    addSettingsJson(options, out, a, json);
  } else {
    addEstimatorSettingsJson(options, out, a, json);
  }
  addMethodsJson(a, json);
  addTruthJson(a, json);
  addBreakdownJson(a, json);
  if (a.rayTraced()) {
    addSceneStatisticsJson(a.sweep, a.scene_stats, json);
  } else {
    json["ranking_tests"] = rankingTestsJson(a.sweep, a.scene_stats.ranking);
  }
  addMethodJackknifeJson(a, json);
  Json parts = Json::object();
  for (const auto& [part, s] : a.part_seconds) parts[part] = s;
  json["timings"] = {{"seconds", seconds}, {"parts", parts}};
  return json;
}

}  // namespace gtbake
