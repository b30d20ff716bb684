#include "fit/fit_report.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/atomic_file.h"
#include "common/output_set.h"
#include "common/text_escape.h"
#include "gtbake_version.h"
#include "plot/svg_plot.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

// Scatter points drawn per scene and albedo (points; ~600 keeps each SVG under ~0.5 MB while
// showing the spread; picked with a fixed stride, so the figure is deterministic).
constexpr std::size_t kScatterPerScene = 600;
// Samples of each drawn curve (points; smooth at the plot size).
constexpr int kCurveSamples = 101;

// One colour per albedo, viridis control points (dark = low ρ).
const char* albedoColor(std::size_t j, std::size_t count) {
  static const char* const kRamp[7] = {"#440154", "#443983", "#31688e", "#21918c",
                                       "#35b779", "#90d743", "#e8c21e"};
  const std::size_t index = count <= 1 ? 0 : j * 6 / (count - 1);
  return kRamp[std::min<std::size_t>(index, 6)];
}

std::vector<double> sampleA() {
  std::vector<double> xs;
  for (int i = 0; i < kCurveSamples; ++i) xs.push_back(i / double(kCurveSamples - 1));
  return xs;
}

void curveOf(SvgPlot& plot, const Cubic& theta, const char* color, bool dashed) {
  std::vector<double> ys;
  for (double A : sampleA()) ys.push_back(evalCubic(theta, A));
  plot.curve(sampleA(), ys, color, dashed);
}

std::string table(const std::vector<std::string>& header,
                  const std::vector<std::vector<std::string>>& rows) {
  std::string html = "<table><tr>";
  for (const auto& h : header) html += "<th>" + h + "</th>";
  html += "</tr>\n";
  for (const auto& row : rows) {
    html += "<tr>";
    for (const auto& cell : row) html += "<td>" + cell + "</td>";
    html += "</tr>\n";
  }
  return html + "</table>\n";
}

std::string curveDistance(const CurveDifference& d) {
  return formatNumber(d.value, "%.4f") + " (A " + formatNumber(d.A, "%.2f") + ", &rho; " +
         formatNumber(d.rho, "%.2f") + ")";
}

// Collects the figures of the page: each staged beside index.html.
class Figures {
 public:
  Figures(OutputSet& set, std::string prefix) : set_(set), prefix_(std::move(prefix)) {}
  void add(const std::string& name, const SvgPlot& plot) {
    set_.add(prefix_ + name, plot.str());
    html_ += "<img src='" + escapeHtml(name) + "' alt='" + escapeHtml(name) + "'>\n";
  }
  void heading(const std::string& text) { html_ += text; }
  std::string html() const { return html_; }

 private:
  OutputSet& set_;
  std::string prefix_;
  std::string html_;
};

// G_shipped − G_refit per albedo against ±t·SE_G, and G(A) per albedo with the band.
void bandFigures(const FitAnalysis& a, const MultiBounceCoeffs& shipped, Figures& figures) {
  const SceneJackknife& jk = a.jackknife;
  const MultiBounceCoeffs& refit = a.fit.linear.coeffs;
  const std::size_t M = a.data.albedos.size();
  const std::vector<double> xs = sampleA();
  const auto band = [&](double A, double rho) {
    return jk.available ? jk.threshold * jackknifeBand(jk, A, rho) : 0.0;
  };
  SvgPlot plot(0, 1, 0, 1, "G(A): refit with band (solid), shipped (dashed)", "A", "G");
  plot.legendBottomRight(static_cast<int>(M));
  for (std::size_t j = M; j-- > 0;) {
    const double rho = a.data.albedos[j];
    std::vector<double> lo, hi;
    for (double A : xs) {
      lo.push_back(evalMultiBounce(refit, A, rho) - band(A, rho));
      hi.push_back(evalMultiBounce(refit, A, rho) + band(A, rho));
    }
    if (jk.available) plot.band(xs, lo, hi, albedoColor(j, M), 0.35);
    curveOf(plot, cubicAt(refit, rho), albedoColor(j, M), false);
    curveOf(plot, cubicAt(shipped, rho), albedoColor(j, M), true);
    plot.legend("&#961; = " + formatNumber(rho, "%.2f"), albedoColor(j, M));
  }
  figures.heading(
      "<h2>Eq. 10: refit (solid, simultaneous band &#177;c SE shaded) against the shipped "
      "constants (dashed), G(A) per albedo</h2>\n");
  figures.add("refit_vs_shipped.svg", plot);
  if (!jk.available) return;
  figures.heading(
      "<h2>The band per albedo: G<sub>shipped</sub> &minus; G<sub>refit</sub> (dashed) against "
      "&#177;c&middot;SE<sub>G</sub> (shaded), simultaneous max-t c = " +
      formatNumber(jk.threshold, "%.2f") + "</h2>\n");
  double span = 0.0;
  for (double rho : a.data.albedos) {
    for (double A : xs) {
      span =
          std::max({span, jk.threshold * jackknifeBand(jk, A, rho),
                    std::abs(evalMultiBounce(shipped, A, rho) - evalMultiBounce(refit, A, rho))});
    }
  }
  for (std::size_t j = 0; j < M; ++j) {
    const double rho = a.data.albedos[j];
    SvgPlot panel(0, 1, -1.05 * span, 1.05 * span, "&#961; = " + formatNumber(rho, "%.2f"), "A",
                  "G &#8722; G(refit)");
    std::vector<double> lo, hi, diff, zero(xs.size(), 0.0);
    for (double A : xs) {
      lo.push_back(-band(A, rho));
      hi.push_back(band(A, rho));
      diff.push_back(evalMultiBounce(shipped, A, rho) - evalMultiBounce(refit, A, rho));
    }
    panel.band(xs, lo, hi, "#c0392b");
    panel.curve(xs, zero, "#c0392b");
    panel.curve(xs, diff, "#333", true);
    panel.legend("refit &#177; c SE (scene jackknife)", "#c0392b");
    panel.legend("shipped", "#333", true);
    figures.add("band_rho" + formatNumber(100 * rho, "%03.0f") + ".svg", panel);
  }
}

// Figure 7: the per-albedo cubics, and a(ρ), b(ρ), c(ρ) with their lines and bands.
void figure7(const FitAnalysis& a, const MultiBounceCoeffs& shipped, Figures& figures) {
  const MultiBounceFit& fit = a.fit;
  const SceneJackknife& jk = a.jackknife;
  const std::size_t M = a.data.albedos.size();
  figures.heading(
      "<h2>Figure 7: per-albedo cubics, and their coefficients against &rho; (bars &#177;2 SE "
      "Monte Carlo, shaded &#177;t SE scene jackknife of the line, pointwise t)</h2>\n");
  {
    SvgPlot plot(0, 1, 0, 1, "per-albedo cubic fits", "A", "G");
    plot.legendBottomRight(static_cast<int>(M));
    for (std::size_t j = M; j-- > 0;) {
      curveOf(plot, fit.per_albedo[j].theta, albedoColor(j, M), false);
      plot.legend("&#961; = " + formatNumber(a.data.albedos[j], "%.2f"), albedoColor(j, M));
    }
    figures.add("fig7_cubics.svg", plot);
  }
  const std::vector<double> rhos = {0.0, 0.25, 0.5, 0.75, 1.0};
  for (int q = 0; q < 3; ++q) {
    const auto line = [&](const MultiBounceCoeffs& k, double rho) {
      return k[2 * q] * rho + k[2 * q + 1];
    };
    const auto lineSe = [&](double rho) {
      if (!jk.available) return 0.0;
      const double v = jk.covariance[6 * (2 * q) + 2 * q] * rho * rho +
                       2.0 * jk.covariance[6 * (2 * q) + 2 * q + 1] * rho +
                       jk.covariance[6 * (2 * q + 1) + 2 * q + 1];
      return jk.pointwise_threshold * std::sqrt(std::max(v, 0.0));
    };
    double lo = 1e9, hi = -1e9;
    for (const AlbedoFit& f : fit.per_albedo) {
      lo = std::min({lo, f.theta[q], f.uncorrected[q]});
      hi = std::max({hi, f.theta[q], f.uncorrected[q]});
    }
    for (double rho : rhos) {
      for (const MultiBounceCoeffs* k : {&fit.linear.coeffs, &shipped}) {
        lo = std::min(lo, line(*k, rho) - lineSe(rho));
        hi = std::max(hi, line(*k, rho) + lineSe(rho));
      }
    }
    const double pad = 0.05 * (hi - lo + 1e-9);
    SvgPlot plot(0, 1, lo - pad, hi + pad, std::string(kCubicNames[q]) + "(&#961;)",
                 "&#961; (albedo)", kCubicNames[q]);
    std::vector<double> ys, band_lo, band_hi, paper;
    for (double rho : rhos) {
      ys.push_back(line(fit.linear.coeffs, rho));
      band_lo.push_back(ys.back() - lineSe(rho));
      band_hi.push_back(ys.back() + lineSe(rho));
      paper.push_back(line(shipped, rho));
    }
    if (jk.available) plot.band(rhos, band_lo, band_hi, "#c0392b");
    plot.curve(rhos, ys, "#c0392b");
    plot.curve(rhos, paper, "#888", true);
    for (const AlbedoFit& f : fit.per_albedo) plot.errorBar(f.rho, f.theta[q], 2 * f.se[q], "#222");
    plot.legend("refit line &#177; t SE (scenes)", "#c0392b");
    plot.legend("shipped (paper) line", "#888", true);
    figures.add(std::string("fig7_") + kCubicNames[q] + ".svg", plot);
  }
}

// Figure 6: A vs G per view, every albedo, with the pooled per-albedo cubics.
void figure6(const FitAnalysis& a, Figures& figures) {
  const std::size_t M = a.data.albedos.size();
  figures.heading("<h2>Figure 6: A vs G per view, every albedo, with the per-albedo cubics</h2>\n");
  for (const SweepScene& scene : a.data.scenes) {
    SvgPlot plot(0, 1, 0, 1, escapeHtml(scene.name), "A (ambient occlusion)", "G (multi-bounce)");
    const std::size_t stride =
        std::max<std::size_t>(1, (scene.end - scene.begin) / kScatterPerScene);
    for (std::size_t j = 0; j < M; ++j) {
      std::vector<double> xs, ys;
      for (std::size_t i = scene.begin; i < scene.end; i += stride) {
        xs.push_back(a.data.full.A[i]);
        ys.push_back(a.data.full.G[j][i]);
      }
      plot.points(xs, ys, albedoColor(j, M));
    }
    for (std::size_t j = 0; j < M; ++j) curveOf(plot, a.fit.per_albedo[j].theta, "#000", false);
    plot.legendBottomRight(1);
    plot.legend("per-albedo cubic (all scenes)", "#000");
    figures.add("fig6_" + fileSlug(scene.name) + ".svg", plot);
  }
}

// The shipped constants' verdict by range of A (docs/fit.md §5): one row per range.
std::string rangeVerdict(const CurveVerdict& v) {
  std::vector<std::vector<std::string>> rows;
  for (std::size_t r = 0; r < v.ranges.size(); ++r) {
    const RangeScore& s = v.ranges[r];
    rows.push_back(
        {rangeLabel(v, r), formatNumber(100.0 * s.pixel_share, "%.1f") + " %",
         formatNumber(s.detectable.value), formatNumber(s.max_difference.value),
         formatNumber(s.max_ratio.value, "%.2f") + " / " + formatNumber(s.threshold, "%.2f"),
         "<b>" + std::string(verdictName(s.verdict)) + "</b>", escapeHtml(s.text)});
  }
  return "<p><b>Shipped constants by range of A: " + escapeHtml(v.headline) + ".</b></p>\n" +
         table({"A range", "pixels", "detectable |&Delta;G|", "max |&Delta;G|",
                "max |&Delta;G|/band / threshold", "verdict", "why"},
               rows);
}

std::string headline(const FitAnalysis& a, const CurveVerdict* verdict) {
  const SceneJackknife& jk = a.jackknife;
  std::string html = "<h2>How sure: the curve band</h2>\n<p>";
  if (jk.available) {
    html +=
        "Scene-jackknife standard error of G(A, &rho;) over A&isin;(0,1], "
        "&rho;&isin;[0.1,0.9]: largest <b>" +
        formatNumber(jk.band_max.value) + "</b> at A = " + formatNumber(jk.band_max.A, "%.3f") +
        ", &rho; = " + formatNumber(jk.band_max.rho, "%.2f") + " (" + std::to_string(jk.scenes) +
        " scenes). Monte Carlo SE of G (another seed): largest " +
        formatNumber(jk.mc_band_max.value, "%.5f") + ".";
  } else {
    html += escapeHtml(jk.message) + ".";
  }
  html += "</p>\n";
  if (verdict != nullptr) html += rangeVerdict(*verdict);
  html += "<p>Over the whole grid (one maximum, dominated by A &rarr; 1): " +
          escapeHtml(a.shipped_score.verdict) +
          ". Largest |G<sub>refit</sub> &minus; G<sub>shipped</sub>|: " +
          curveDistance(a.shipped_difference) + ".</p>\n";
  return html;
}

std::string coefficientTables(const FitAnalysis& a, const MultiBounceCoeffs& shipped) {
  const LinearFit& lin = a.fit.linear;
  const SceneJackknife& jk = a.jackknife;
  std::vector<std::vector<std::string>> rows;
  for (int i = 0; i < 6; ++i) {
    rows.push_back(
        {kCoeffNames[i], formatNumber(lin.coeffs[i]),
         jk.available ? formatNumber(jk.se[i]) : "&ndash;", formatNumber(lin.se[i], "%.5f"),
         formatNumber(shipped[i]),
         jk.available ? formatNumber((shipped[i] - lin.coeffs[i]) / jk.se[i], "%.1f") : "&ndash;",
         formatNumber(lin.eiv_bias[i], "%+.5f"),
         formatNumber(remainingBias(lin.eiv_bias[i], lin.eiv_bias_quadratic[i],
                                    a.fit.settings.eiv_correction),
                      "%.5f")});
  }
  std::string html =
      "<h2>Linear coefficients</h2>\n" +
      table({"coef", "refit", "SE (scenes)", "SE (Monte Carlo)", "shipped",
             "(shipped&minus;refit)/SE scenes", "EIV bias", "bias left"},
            rows) +
      "<p>SE (scenes): delete-one-scene jackknife, what the choice of scenes moves. SE (Monte "
      "Carlo): what a rerun with another seed moves. EIV bias: measured bias of the uncorrected "
      "fit from noise in A; bias left: what remains in the reported value. See docs/fit.md.</p>\n";
  if (jk.available) {
    std::vector<std::vector<std::string>> corr;
    for (int r = 0; r < 6; ++r) {
      std::vector<std::string> row = {kCoeffNames[r]};
      for (int c = 0; c < 6; ++c) row.push_back(formatNumber(jk.correlation[6 * r + c], "%+.3f"));
      corr.push_back(row);
    }
    html += "<h3>Scene-jackknife correlation</h3>\n" +
            table({"", kCoeffNames[0], kCoeffNames[1], kCoeffNames[2], kCoeffNames[3],
                   kCoeffNames[4], kCoeffNames[5]},
                  corr);
  }
  return html;
}

std::string alternativeTables(const FitAnalysis& a) {
  std::vector<std::vector<std::string>> rows;
  for (const Alternative& alt : a.weightings) {
    rows.push_back({alt.name, curveDistance(alt.vs_default), formatNumber(alt.linear[0]),
                    formatNumber(alt.linear[2]), formatNumber(alt.linear[4]),
                    formatNumber(alt.rmse, "%.5f")});
  }
  const OpenSurface& o = a.open_surface;
  const double cost = constraintCost(a);
  return "<h2>Point weighting and the open surface</h2>\n" +
         table({"weighting", "max |&Delta;G| vs pixel", "a1", "b1", "c1", "RMSE"}, rows) +
         "<p>G(1, &rho;) of the refit = " + formatNumber(o.intercept, "%.5f") + " " +
         formatNumber(o.slope, "%+.5f") + " &rho; (an open surface gives 1). " +
         (a.fit.settings.shape_constrained
              ? "The shape constraints (G(1, &rho;) = 1, dG/dA &ge; 0, G &ge; 0)"
              : "The constraint a &minus; b + c = 1 (--constrain-open)") +
         " changes the RMSE by " + formatNumber(cost, "%+.2e") + "; the curves differ by " +
         formatNumber(a.constraint.vs_default.value) + " at most.</p>\n";
}

std::string errorTables(const FitAnalysis& a) {
  std::vector<std::vector<std::string>> rows;
  const ErrorTable& r = a.refit_errors;
  const ErrorTable& s = a.shipped_errors;
  for (std::size_t j = 0; j < r.per_albedo.size(); ++j) {
    rows.push_back({"&rho; = " + r.per_albedo[j].label, formatNumber(r.per_albedo[j].rmse, "%.5f"),
                    formatNumber(a.floor.per_albedo[j].floor, "%.5f"),
                    formatNumber(r.per_albedo[j].max_abs, "%.5f"),
                    formatNumber(s.per_albedo[j].rmse, "%.5f"),
                    formatNumber(s.per_albedo[j].max_abs, "%.5f"), "", ""});
  }
  for (std::size_t k = 0; k < r.per_scene.size(); ++k) {
    rows.push_back(
        {escapeHtml(r.per_scene[k].label), formatNumber(r.per_scene[k].rmse, "%.5f"),
         formatNumber(a.floor.per_scene[k].floor, "%.5f"),
         formatNumber(r.per_scene[k].max_abs, "%.5f"), formatNumber(s.per_scene[k].rmse, "%.5f"),
         formatNumber(s.per_scene[k].max_abs, "%.5f"), std::to_string(a.view_weights[k].points),
         formatNumber(100 * a.view_weights[k].share, "%.1f") + "%"});
  }
  rows.push_back({"all", formatNumber(r.rmse, "%.5f"), formatNumber(a.floor.rmse, "%.5f"),
                  formatNumber(r.max_abs, "%.5f"), formatNumber(s.rmse, "%.5f"),
                  formatNumber(s.max_abs, "%.5f"), std::to_string(a.data.points()), "100%"});
  return "<h2>Errors of G against the path-traced data, and the floor</h2>\n" +
         table({"", "refit RMSE", "floor RMSE", "refit max|e|", "shipped RMSE", "shipped max|e|",
                "points", "weight"},
               rows) +
         "<p>Floor: RMSE of the best function of (A, &rho;) alone on the same points (conditional "
         "mean in " +
         std::to_string(kFloorBins) +
         " bins of A, small-sample corrected): the scatter no G(A, &rho;) can remove. Weight: the "
         "view's share of the fit's total weight.</p>\n";
}

std::string leaveOneOutTable(const SceneJackknife& jk) {
  if (jk.leave_one_out.empty()) return "";
  std::vector<std::vector<std::string>> rows;
  for (const LeaveOneOut& r : jk.leave_one_out) {
    rows.push_back({escapeHtml(r.left_out), formatNumber(r.linear[0]), formatNumber(r.linear[2]),
                    formatNumber(r.linear[4]), curveDistance(r.vs_refit),
                    curveDistance(r.vs_shipped)});
  }
  const std::string band = jk.available ? " &mdash; band max " + formatNumber(jk.band_max.value) +
                                              ", SE a1 " + formatNumber(jk.se[0])
                                        : " &mdash; " + jk.message;
  return "<h2>Leave one " + jk.unit + " out (" + std::to_string(jk.scenes) + " " + jk.unit +
         "s, the jackknife's replicas" + band + ")</h2>\n" +
         table(
             {"left out", "a1", "b1", "c1", "max |&Delta;G| vs refit", "max |&Delta;G| vs shipped"},
             rows);
}

// One thumbnail of A per view: the sweep's <view>_A.png, verified against its manifest and copied
// into views/ below the page, so the report holds every image it shows (docs/reproducibility.md
// "Layout"). A sweep set without previews gets no thumbnails.
std::string thumbnails(const FitAnalysis& a, OutputSet& set, const std::string& prefix) {
  const OutputManifest sweep = readOutputSet(a.data.dir, "sweep");
  std::string html = "<h2>Views (A, the sweep's previews)</h2>\n<div>";
  for (const SweepScene& sc : a.data.scenes) {
    const std::string png = fileSlug(sc.name) + "_A.png";
    if (sweep.find(png) == nullptr) continue;
    const std::string src = "views/" + png;
    set.add(prefix + src, sweep.readVerified(png));
    const std::string name = escapeHtml(sc.name);
    html += "<figure style='display:inline-block;margin:4px;text-align:center'><img src=\"" +
            escapeHtml(src) + "\" width=96 height=96 alt=\"" + name +
            "\"><figcaption style='font-size:11px'>" + name +
            (sc.type == sc.name ? "" : "<br>" + escapeHtml(sc.type)) + "</figcaption></figure>";
  }
  return html + "</div>\n";
}

std::string perAlbedoTable(const MultiBounceFit& fit) {
  std::vector<std::vector<std::string>> rows;
  for (const AlbedoFit& f : fit.per_albedo) {
    std::vector<std::string> row = {formatNumber(f.rho, "%.2f")};
    for (int q = 0; q < 3; ++q) {
      row.push_back(formatNumber(f.theta[q]) + " &#177; " + formatNumber(f.se[q], "%.5f"));
      row.push_back(formatNumber(f.eiv_bias[q], "%+.5f"));
    }
    row.push_back(formatNumber(f.rmse, "%.5f"));
    row.push_back(formatNumber(f.max_abs, "%.5f"));
    rows.push_back(row);
  }
  const Cubic& rms = fit.linear.lack_of_fit_rms;
  return "<h2>Per-albedo cubics</h2>\n" +
         table({"&rho;", "a &#177; SE MC", "EIV bias a", "b &#177; SE MC", "EIV bias b",
                "c &#177; SE MC", "EIV bias c", "RMSE", "max|e|"},
               rows) +
         "<p>Lack of fit of the lines in &rho; (model error of the linear-in-&rho; law, not an "
         "uncertainty): RMS residual a " +
         formatNumber(rms[0]) + ", b " + formatNumber(rms[1]) + ", c " + formatNumber(rms[2]) +
         ".</p>\n";
}

}  // namespace

void writeFitReport(OutputSet& set, const std::string& prefix, const FitAnalysis& a,
                    const MultiBounceCoeffs& shipped, const CurveVerdict* verdict) {
  Figures figures(set, prefix);
  bandFigures(a, shipped, figures);
  figure7(a, shipped, figures);
  figure6(a, figures);
  const FitSettings& s = a.fit.settings;
  std::string scenes;
  for (const SweepScene& sc : a.data.scenes) {
    scenes += (scenes.empty() ? "" : ", ") + escapeHtml(sc.name);
  }
  const std::string html =
      "<!DOCTYPE html>\n<html><head><meta charset='utf-8'><title>gtbake fit report</title>\n"
      "<style>body{font-family:sans-serif;margin:24px;max-width:1400px}"
      "table{border-collapse:collapse;margin:8px 0 20px}"
      "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}"
      "th{background:#f3f3f3}img{margin:4px;border:1px solid #eee}</style></head><body>\n"
      "<h1>gtbake fit: multi-bounce Eq. 10</h1>\n<p>Sweep <code>" +
      escapeHtml((a.data.dir / "").lexically_normal().parent_path().filename().string()) +
      "</code>: " + std::to_string(a.data.scenes.size()) + " views of " +
      std::to_string(a.jackknife.scenes) + " scenes of " + std::to_string(a.type_jackknife.scenes) +
      " types (" + scenes + "), " + std::to_string(a.data.points()) + " points, " +
      std::to_string(a.data.spp) + " spp, " + std::to_string(a.data.bounces) +
      " bounces. Weighting " + weightingName(s.weighting) + ", open surface " +
      (s.constrain_open ? "constrained" : "free") + ", EIV correction " +
      (s.eiv_correction ? "on" : "off") + ". gtbake " + GTBAKE_VERSION +
      ". G = a(&rho;)A&sup3; &minus; b(&rho;)A&sup2; + c(&rho;)A.</p>\n" + headline(a, verdict) +
      coefficientTables(a, shipped) + alternativeTables(a) + errorTables(a) +
      leaveOneOutTable(a.jackknife) + leaveOneOutTable(a.type_jackknife) + perAlbedoTable(a.fit) +
      thumbnails(a, set, prefix) + figures.html() + "</body></html>\n";
  set.add(prefix + "index.html", html);
}

}  // namespace gtbake
