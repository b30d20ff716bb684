// validate-gtso's pages, images and summary from analyse()'s result (docs/validate_gtso.md §4):
// formatting only.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "common/image_io.h"
#include "common/output_set.h"
#include "common/text_escape.h"
#include "gtbake_version.h"
#include "sweep/sweep_set.h"
#include "validate_gtso/scene_statistics.h"
#include "validate_gtso/validate_gtso_outputs.h"

namespace gtbake {

namespace {

namespace fs = std::filesystem;

constexpr float kErrorMapMax = 0.5f;  // |error| mapped to the top of the viridis ramp
// The methods of each image row after the truth: 3D, 4D (BC4 as shipped), cone (fitted u).
constexpr Method kImageMethods[] = {Method::kS3Bc4, Method::kS4Bc4, Method::kConeFittedU};

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

// The page's head, its introduction (what A and b are) and the RMSE-by-roughness table with the
// best method per roughness.
void writeMethodTable(const Analysis& a, std::ostringstream& o) {
  const SpecularSweep& sweep = a.sweep;
  const Tables& t = a.t;
  const std::vector<Method>& methods = a.methods;
  const std::vector<std::vector<Method>>& ranking = a.ranking;
  o << "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>gtbake validate-gtso</title>"
       "<style>body{font-family:sans-serif;max-width:1100px;margin:1em auto}table{border-"
       "collapse:collapse}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
       "td:first-child{text-align:left}img{max-width:100%}</style></head><body>\n";
  o << "<h1>GTSO against path-traced specular occlusion</h1>\n<p>gtbake " << GTBAKE_VERSION
    << ". Every unmasked pixel of " << sweep.scenes.size() << " views; truth: GGX (alpha = r_p^2, "
    << "height-correlated Smith, F = 1) against the binary sky visibility, " << sweep.specular_spp
    << " VNDF samples per pixel. ";
  if (a.rayTraced()) {
    o << "Every method reads the sweep's ray-traced A and bent normal. Companion of the fit "
         "report (fit/report/index.html in the layout of gtbake all); ";
  } else {
    o << "Every method reads <b>" << escapeHtml(a.estimator)
      << "</b>'s screen-space A and bent normal, as the runtime has them (u fitted on the "
         "ray-traced inputs: "
      << fmt("%.3g", a.shipped_u) << "); ";
  }
  o << "numbers in validate_gtso.json, method in docs/validate_gtso.md.</p>\n";
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
  o << ".</p>\n";
}

// The view images, one per view (writeSceneImages), and the end of the page.
void writeScenesSection(const SpecularSweep& sweep, bool images, std::ostringstream& o) {
  if (!images) {
    o << "<p>Per-view images: run validate-gtso on its own (gtbake all leaves them out of "
         "profiles/).</p>\n</body></html>\n";
    return;
  }
  o << "<h2>Per view (paper Figs. 13&ndash;14)</h2>\n<p>Columns: path-traced S | "
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
}

// The ray-traced page: the method table, texel formats, u and the out-of-plane table.
std::string rayTracedPage(const Analysis& a, bool images) {
  const Tables& t = a.t;
  const UFits& spec = a.spec;
  const UFits& perceptual = a.perceptual;
  std::ostringstream o;
  writeMethodTable(a, o);
  o << "<h2>Texel formats against the float table at the same pixels</h2>\n"
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
  o << "</table>\n";
  writeScenesSection(a.sweep, images, o);
  return o.str();
}

// The page on an estimator's inputs: the method table, the scene-level ranking statements.
std::string estimatorPage(const Analysis& a, bool images) {
  std::ostringstream o;
  writeMethodTable(a, o);
  o << "<h2>Scene-level rankings</h2>\n<ul>\n";
  for (std::size_t j = 0; j < a.scene_stats.ranking.size(); ++j) {
    o << "<li>r_p " << fmt("%.2f", a.sweep.roughness[j]) << ": "
      << escapeHtml(a.scene_stats.ranking[j].statement) << "</li>\n";
  }
  o << "</ul>\n";
  writeScenesSection(a.sweep, images, o);
  return o.str();
}

// The four u fits, one line each.
void printUFits(const UFits& spec, const UFits& perceptual) {
  auto line = [](const char* name, const UFit& f) {
    std::printf("  u %-28s %.3g %s  RMSE %.4f (u=0.01: %.4f, u=0.244: %.4f)\n", name, f.u,
                intervalText(f).c_str(), f.rmse, f.rmse_paper, f.rmse_uludag);
  };
  line("u^(alpha^2/2), all r_p", spec.all);
  line("u^(alpha^2/2), r_p >= 0.3", spec.rp_ge_0_3);
  line("u^(r_p^2/2), all r_p", perceptual.all);
  line("u^(r_p^2/2), r_p >= 0.3", perceptual.rp_ge_0_3);
}

}  // namespace

void printValidateGtsoSummary(const Analysis& a, const fs::path& json) {
  const SpecularSweep& sweep = a.sweep;
  const Tables& t = a.t;
  std::vector<int> cluster_of;
  std::printf(
      "validate-gtso: %zu pixels x %zu roughness values, %zu views of %zu scenes (specular spp "
      "%d)%s%s\n",
      a.samples.size() / sweep.roughness.size(), sweep.roughness.size(), sweep.scenes.size(),
      sceneClusters(sweep, cluster_of).size(), sweep.specular_spp,
      a.rayTraced() ? "" : ", inputs of ", a.estimator.c_str());
  std::printf("  RMSE vs path-traced S    ");
  for (double r : sweep.roughness) std::printf("  r_p %.2f", r);
  std::printf("      all  mean err\n");
  for (Method m : a.methods) {
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
  for (std::size_t j = 0; j < a.ranking.size(); ++j) {
    std::printf(" r_p %.2f %s;", sweep.roughness[j], methodName(a.ranking[j][0]));
  }
  std::printf("\n");
  if (a.rayTraced()) printUFits(a.spec, a.perceptual);
  std::printf("  wrote %s\n", json.c_str());
}

void addValidateGtsoReport(const Analysis& a, bool images, OutputSet& output) {
  if (images) writeSceneImages(a.sweep, a.samples, a.values, output);
  if (a.rayTraced()) {
    output.add("report/validate_gtso.html", rayTracedPage(a, images));
    output.add("report/validate_gtso_scenes.html", sceneStatisticsHtml(a.sweep, a.scene_stats));
  } else {
    output.add("report/validate_gtso.html", estimatorPage(a, images));
  }
}

}  // namespace gtbake
