// `gtbake validate-gtso`: read the sweep and the tables, evaluate every method at every pixel and
// roughness, fit u, then write validate_gtso.json, the per-scene image rows and the HTML page, and
// print the one-screen summary.
#include "validate_gtso/validate_gtso_command.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/output_lock.h"
#include "common/output_set.h"
#include "common/text_escape.h"
#include "gtbake_version.h"
#include "sweep/escape_image.h"
#include "validate_gtso/cone_u_fit.h"
#include "validate_gtso/gtso_lookup.h"
#include "validate_gtso/method_jackknife.h"
#include "validate_gtso/scene_statistics.h"
#include "validate_gtso/specular_methods.h"
#include "validate_gtso/specular_sweep.h"
#include "validate_gtso/validate_gtso_analysis.h"

namespace gtbake {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

constexpr float kErrorMapMax = 0.5f;  // |error| mapped to the top of the viridis ramp
// The methods of each image row after the truth: 3D, 4D (BC4 as shipped), cone (fitted u).
constexpr Method kImageMethods[] = {Method::kS3Bc4, Method::kS4Bc4, Method::kConeFittedU};

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

// Per scene one RGB image: a row per roughness of panels truth | S₃ | S₄ | cone | |S₄ − truth|.
void writeSceneImages(const SpecularSweep& sweep, const std::vector<SpecularSample>& samples,
                      const std::vector<std::vector<float>>& values, OutputSet& output) {
  constexpr int kPanels = 5;
  // Each scene's samples found in one pass, and the scenes drawn and encoded in parallel (added to
  // the set in scene order).
  std::vector<std::vector<std::size_t>> of_scene(sweep.scenes.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    of_scene[static_cast<std::size_t>(samples[i].scene)].push_back(i);
  }
  std::vector<std::string> png(sweep.scenes.size());
  tbb::parallel_for(std::size_t{0}, sweep.scenes.size(), [&](std::size_t sc) {
    const SpecularScene& scene = sweep.scenes[sc];
    const int w = scene.width;
    const int h = scene.height;
    const int rows = static_cast<int>(sweep.roughness.size());
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(kPanels) * w * rows * h * 3, 0);
    auto put = [&](int row, int panel, std::size_t p, const std::uint8_t* c) {
      const std::size_t x = static_cast<std::size_t>(panel) * w + p % w;
      const std::size_t y = static_cast<std::size_t>(row) * h + p / w;
      std::copy(c, c + 3, &rgb[(y * kPanels * w + x) * 3]);
    };
    for (std::size_t i : of_scene[sc]) {
      const SpecularSample& s = samples[i];
      const float panel_values[4] = {static_cast<float>(s.truth),
                                     values[static_cast<int>(kImageMethods[0])][i],
                                     values[static_cast<int>(kImageMethods[1])][i],
                                     values[static_cast<int>(kImageMethods[2])][i]};
      for (int panel = 0; panel < 4; ++panel) {
        const float v = std::clamp(panel_values[panel], 0.0f, 1.0f);
        const auto g = static_cast<std::uint8_t>(std::lround(255.0f * v));
        const std::uint8_t c[3] = {g, g, g};
        put(s.roughness, panel, s.pixel, c);
      }
      const float err = std::abs(panel_values[2] - panel_values[0]);
      put(s.roughness, 4, s.pixel, toViridis8({err}, 0.0f, kErrorMapMax).data());
    }
    png[sc] = encodePng(kPanels * w, rows * h, 3, rgb);
  });
  for (std::size_t sc = 0; sc < sweep.scenes.size(); ++sc) {
    output.add("report/validate_gtso_" + fileSlug(sweep.scenes[sc].name) + ".png", png[sc]);
  }
}

std::string fmt(const char* format, double v) {
  char text[64];
  std::snprintf(text, sizeof(text), format, v);
  return text;
}

std::string intervalText(const UFit& f) {
  return "[" + std::string(f.low_open ? "<=" : "") + fmt("%.3g", f.low) + ", " +
         (f.high_open ? ">=" : "") + fmt("%.3g", f.high) + "]";
}

void writePage(const SpecularSweep& sweep, const Tables& t, const std::vector<Method>& methods,
               const std::vector<std::vector<Method>>& ranking, const UFits& spec,
               const UFits& perceptual, OutputSet& output) {
  std::ostringstream o;
  o << "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>gtbake validate-gtso</title>"
       "<style>body{font-family:sans-serif;max-width:1100px;margin:1em auto}table{border-"
       "collapse:collapse}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
       "td:first-child{text-align:left}img{max-width:100%}</style></head><body>\n";
  o << "<h1>GTSO against path-traced specular occlusion</h1>\n<p>gtbake " << GTBAKE_VERSION
    << ". Every unmasked pixel of " << sweep.scenes.size() << " scenes; truth: GGX (alpha = r_p^2, "
    << "height-correlated Smith, F = 1) against the binary sky visibility, " << sweep.specular_spp
    << " VNDF samples per pixel. Companion of the <a href=\"index.html\">fit report</a>; "
       "numbers in validate_gtso.json, method in docs/validate_gtso.md.</p>\n";
  o << "<h2>RMSE by roughness</h2>\n<table><tr><th>method</th>";
  for (double r : sweep.roughness) o << "<th>r_p " << fmt("%.2f", r) << "</th>";
  o << "<th>all</th><th>mean signed</th><th>max |err|</th></tr>\n";
  for (Method m : methods) {
    o << "<tr><td>" << methodName(m) << " &mdash; " << methodDescription(m) << "</td>";
    for (std::size_t j = 0; j < sweep.roughness.size(); ++j) {
      o << "<td>" << fmt("%.4f", t.per_roughness[static_cast<int>(m)][j].rmse()) << "</td>";
    }
    const ErrorStats& e = t.overall[static_cast<int>(m)];
    o << "<td>" << fmt("%.4f", e.rmse()) << "</td><td>" << fmt("%+.4f", e.meanSigned())
      << "</td><td>" << fmt("%.3f", e.max_abs) << "</td></tr>\n";
  }
  o << "</table>\n<p>Best method per roughness: ";
  for (std::size_t j = 0; j < ranking.size(); ++j) {
    o << (j ? "; " : "") << "r_p " << fmt("%.2f", sweep.roughness[j]) << ": "
      << methodName(ranking[j][0]);
  }
  o << ".</p>\n<h2>Texel formats against the float table at the same pixels</h2>\n"
       "<table><tr><th>method</th><th>RMS of method &minus; float</th><th>mean signed</th>"
       "<th>max |method &minus; float|</th></tr>\n";
  for (int f = 0; f < kFormatMethodCount; ++f) {
    const ErrorStats& e = t.vs_float[f];
    o << "<tr><td>" << methodName(kFormatMethods[f].first) << " vs "
      << methodName(kFormatMethods[f].second) << "</td><td>" << fmt("%.2e", e.rmse()) << "</td><td>"
      << fmt("%+.2e", e.meanSigned()) << "</td><td>" << fmt("%.2e", e.max_abs) << "</td></tr>\n";
  }
  o << "</table>\n<h2>Cone aperture u</h2>\n<table><tr><th>convention</th><th>pixels</th><th>u</th>"
       "<th>RMSE within 5% (flatness, not a CI)</th><th>RMSE at u</th><th>at 0.01</th><th>at "
       "0.244</th></tr>\n";
  auto fitRow = [&](const char* name, const UFit& f) {
    o << "<tr><td>" << name << "</td><td>" << f.count << "</td><td>" << fmt("%.3g", f.u)
      << "</td><td>" << intervalText(f) << "</td><td>" << fmt("%.4f", f.rmse) << "</td><td>"
      << fmt("%.4f", f.rmse_paper) << "</td><td>" << fmt("%.4f", f.rmse_uludag) << "</td></tr>\n";
  };
  fitRow("u^(alpha^2/2), alpha = r_p^2 (docs/gtso.md §1), all r_p", spec.all);
  fitRow("u^(alpha^2/2), r_p &ge; 0.3", spec.rp_ge_0_3);
  fitRow("u^(r_p^2/2) (perceptual), all r_p", perceptual.all);
  fitRow("u^(r_p^2/2), r_p &ge; 0.3", perceptual.rp_ge_0_3);
  o << "</table>\n<h2>4D table error by how far b leaves the plane of n and wr</h2>\n"
       "<table><tr><th>angle</th><th>samples</th><th>S4 RMSE</th><th>S4 mean signed</th>"
       "<th>S3 RMSE</th></tr>\n";
  for (int b = 0; b < kPlaneBinCount; ++b) {
    o << "<tr><td>" << fmt("%.0f", kPlaneBins[b]) << "&ndash;" << fmt("%.0f", kPlaneBins[b + 1])
      << "&deg;</td><td>" << t.plane[0][b].count << "</td><td>" << fmt("%.4f", t.plane[0][b].rmse())
      << "</td><td>" << fmt("%+.4f", t.plane[0][b].meanSigned()) << "</td><td>"
      << fmt("%.4f", t.plane[1][b].rmse()) << "</td></tr>\n";
  }
  o << "</table>\n<h2>Per scene (paper Figs. 13&ndash;14)</h2>\n<p>Columns: path-traced S | "
       "S3 (BC4) | S4 (BC4) | cone (fitted u) | |S4 &minus; truth| (viridis, 0 to "
    << fmt("%.1f", kErrorMapMax) << "). Rows: r_p ";
  for (std::size_t j = 0; j < sweep.roughness.size(); ++j) {
    o << (j ? ", " : "") << fmt("%.2f", sweep.roughness[j]);
  }
  o << ".</p>\n";
  for (const SpecularScene& scene : sweep.scenes) {
    const std::string name = escapeHtml(scene.name);
    o << "<h3>" << name << "</h3><img src=\"validate_gtso_" << escapeHtml(fileSlug(scene.name))
      << ".png\" alt=\"" << name << "\">\n";
  }
  o << "</body></html>\n";
  output.add("report/validate_gtso.html", o.str());
}

void printSummary(const SpecularSweep& sweep, std::size_t pixels, const Tables& t,
                  const std::vector<Method>& methods,
                  const std::vector<std::vector<Method>>& ranking, const UFits& spec,
                  const UFits& perceptual, const fs::path& json) {
  std::printf("validate-gtso: %zu pixels x %zu roughness values, %zu scenes (specular spp %d)\n",
              pixels, sweep.roughness.size(), sweep.scenes.size(), sweep.specular_spp);
  std::printf("  RMSE vs path-traced S    ");
  for (double r : sweep.roughness) std::printf("  r_p %.2f", r);
  std::printf("      all  mean err\n");
  for (Method m : methods) {
    std::printf("  %-24s", methodName(m));
    for (std::size_t j = 0; j < sweep.roughness.size(); ++j) {
      std::printf("  %8.4f", t.per_roughness[static_cast<int>(m)][j].rmse());
    }
    const ErrorStats& e = t.overall[static_cast<int>(m)];
    std::printf("  %7.4f  %+8.4f\n", e.rmse(), e.meanSigned());
  }
  std::printf("  MC noise of the truth    ");
  for (std::size_t j = 0; j < sweep.roughness.size(); ++j) {
    const ErrorStats& e = t.per_roughness[static_cast<int>(Method::kNone)][j];
    std::printf("  %8.4f", e.count ? std::sqrt(e.noise / e.count) : 0.0);
  }
  std::printf("  (RMS standard error)\n  best:");
  for (std::size_t j = 0; j < ranking.size(); ++j) {
    std::printf(" r_p %.2f %s;", sweep.roughness[j], methodName(ranking[j][0]));
  }
  std::printf("\n");
  auto line = [](const char* name, const UFit& f) {
    std::printf("  u %-28s %.3g %s  RMSE %.4f (u=0.01: %.4f, u=0.244: %.4f)\n", name, f.u,
                intervalText(f).c_str(), f.rmse, f.rmse_paper, f.rmse_uludag);
  };
  line("u^(alpha^2/2), all r_p", spec.all);
  line("u^(alpha^2/2), r_p >= 0.3", spec.rp_ge_0_3);
  line("u^(r_p^2/2), all r_p", perceptual.all);
  line("u^(r_p^2/2), r_p >= 0.3", perceptual.rp_ge_0_3);
  std::printf("  wrote %s\n", json.c_str());
}

// validate_gtso.json: inputs, conventions and the u fits.
void addSettingsJson(const ValidateGtsoOptions& options, const fs::path& out, const Analysis& a,
                     Json& json) {
  const SpecularSweep& sweep = a.sweep;
  json["gtbake_version"] = GTBAKE_VERSION;
  json["sweep"] = {{"dir", relativePath(options.sweep, out)},
                   {"spp", sweep.spp},
                   {"specular_spp", sweep.specular_spp},
                   {"roughness", sweep.roughness},
                   {"scenes", sweep.scenes.size()},
                   {"pixels", a.samples.size() / sweep.roughness.size()}};
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
  for (int f = 0; f < kFormatMethodCount; ++f) {
    const ErrorStats& e = t.vs_float[f];
    vs_float[methodName(kFormatMethods[f].first)] = {
        {"against", methodName(kFormatMethods[f].second)},
        {"count", e.count},
        {"rms", e.rmse()},
        {"mean_signed", e.meanSigned()},
        {"max_abs", e.max_abs}};
  }
  json["format_vs_float"] = vs_float;
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
  json["scenes"] = scenes;
}

}  // namespace

ValidateGtsoResult runValidateGtso(const ValidateGtsoOptions& options) {
  if (options.sweep.empty()) throw Error("validate-gtso: --sweep DIR is required");
  if (options.luts.empty()) throw Error("validate-gtso: --luts DIR is required");
  if (options.u != 0.0 && !(options.u > 0.0 && options.u < 1.0)) {
    throw Error("validate-gtso: --u must lie in (0, 1), got " + fmt("%g", options.u));
  }
  const auto start = std::chrono::steady_clock::now();
  const fs::path out = options.out.empty() ? options.luts : options.out;
  const OutputLock lock(out);  // for the whole run (output_lock.h)
  // Read and compute everything before writing anything.
  const Analysis a = analyse(options);
  Json json;
  addSettingsJson(options, out, a, json);
  addMethodsJson(a, json);
  addBreakdownJson(a, json);
  addSceneStatisticsJson(a.sweep, a.scene_stats, json);
  addMethodJackknifeJson(a, json);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Json parts = Json::object();
  for (const auto& [part, s] : a.part_seconds) parts[part] = s;
  json["timings"] = {{"seconds", seconds}, {"parts", parts}};

  // The page and its images are part of the set (report/ beside validate_gtso.json): a failed
  // run leaves the previous page with the previous JSON.
  const fs::path json_path = out / "validate_gtso.json";
  OutputSet output(out, "validate_gtso");  // export requires and verifies it
  writeSceneImages(a.sweep, a.samples, a.values, output);
  writePage(a.sweep, a.t, a.methods, a.ranking, a.spec, a.perceptual, output);
  output.add("report/validate_gtso_scenes.html", sceneStatisticsHtml(a.sweep, a.scene_stats));
  output.add(json_path.filename().string(), json.dump(2) + "\n");
  output.commit();
  printSummary(a.sweep, a.samples.size() / a.sweep.roughness.size(), a.t, a.methods, a.ranking,
               a.spec, a.perceptual, json_path);

  ValidateGtsoResult result;
  result.json = json_path;
  result.u = a.spec.all.u;
  result.u_low = a.scene_stats.u.interval[0].low;
  result.u_high = a.scene_stats.u.interval[0].high;
  result.seconds = seconds;
  return result;
}

}  // namespace gtbake
