#include "fit/fit_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/atomic_file.h"
#include "gtbake_version.h"

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

std::string fmt(double v, const char* format = "%.4f") {
  char text[64];
  std::snprintf(text, sizeof(text), format, v);
  return text;
}

// A minimal SVG line/scatter plot in data coordinates.
class SvgPlot {
 public:
  SvgPlot(double x0, double x1, double y0, double y1, const std::string& title,
          const std::string& xlabel, const std::string& ylabel)
      : x0_(x0), x1_(x1) {
    // y axis: widen to a multiple of a 1-2-5 step so the tick labels are round numbers.
    const double raw = (y1 - y0) / 5.0;
    const double decade = std::pow(10.0, std::floor(std::log10(raw)));
    const double step = raw <= decade       ? decade
                        : raw <= 2 * decade ? 2 * decade
                        : raw <= 5 * decade ? 5 * decade
                                            : 10 * decade;
    y0_ = std::floor(y0 / step + 1e-9) * step;
    y1_ = std::ceil(y1 / step - 1e-9) * step;
    const int y_ticks = static_cast<int>(std::lround((y1_ - y0_) / step));
    out_ << "<svg xmlns='http://www.w3.org/2000/svg' width='" << kW << "' height='" << kH
         << "' viewBox='0 0 " << kW << ' ' << kH << "' font-family='sans-serif' font-size='12'>\n"
         << "<rect width='100%' height='100%' fill='white'/>\n"
         << "<text x='" << kW / 2 << "' y='18' text-anchor='middle' font-size='14'>" << title
         << "</text>\n"
         << "<text x='" << (kL + kW - kR) / 2 << "' y='" << kH - 6 << "' text-anchor='middle'>"
         << xlabel << "</text>\n"
         << "<text transform='translate(14," << (kT + kH - kB) / 2
         << ") rotate(-90)' text-anchor='middle'>" << ylabel << "</text>\n";
    for (int t = 0; t <= 5; ++t) {
      const double x = x0 + (x1 - x0) * t / 5.0;
      out_ << "<line x1='" << px(x) << "' y1='" << py(y0_) << "' x2='" << px(x) << "' y2='"
           << py(y1_) << "' stroke='#ddd'/>\n<text x='" << px(x) << "' y='" << py(y0_) + 16
           << "' text-anchor='middle'>" << fmt(x, "%.1f") << "</text>\n";
    }
    for (int t = 0; t <= y_ticks; ++t) {
      const double y = y0_ + step * t;
      out_ << "<line x1='" << px(x0) << "' y1='" << py(y) << "' x2='" << px(x1) << "' y2='" << py(y)
           << "' stroke='#ddd'/>\n<text x='" << px(x0) - 4 << "' y='" << py(y) + 4
           << "' text-anchor='end'>" << fmt(std::abs(y) < 1e-12 ? 0.0 : y, "%g") << "</text>\n";
    }
    out_ << "<rect x='" << kL << "' y='" << kT << "' width='" << kW - kL - kR << "' height='"
         << kH - kT - kB << "' fill='none' stroke='black'/>\n";
  }

  // Legends go top-left by default, bottom-right for plots whose curves fill the top-left.
  void legendBottomRight(int rows) { legend_origin_ = {kW - kR - 180, kH - kB - 8 - 16.0 * rows}; }

  void points(const std::vector<double>& xs, const std::vector<double>& ys, const char* color,
              double radius = 1.5) {
    out_ << "<g fill='" << color << "' fill-opacity='0.45'>";
    for (std::size_t i = 0; i < xs.size(); ++i) {
      out_ << "<circle cx='" << fmt(px(xs[i]), "%.1f") << "' cy='" << fmt(py(ys[i]), "%.1f")
           << "' r='" << radius << "'/>";
    }
    out_ << "</g>\n";
  }

  void curve(const std::vector<double>& xs, const std::vector<double>& ys, const char* color,
             bool dashed = false, double width = 1.6) {
    out_ << "<polyline fill='none' stroke='" << color << "' stroke-width='" << width << "'"
         << (dashed ? " stroke-dasharray='5,4'" : "") << " points='";
    for (std::size_t i = 0; i < xs.size(); ++i) {
      out_ << fmt(px(xs[i]), "%.1f") << ',' << fmt(py(ys[i]), "%.1f") << ' ';
    }
    out_ << "'/>\n";
  }

  void errorBar(double x, double y, double half, const char* color) {
    out_ << "<line x1='" << px(x) << "' y1='" << py(y - half) << "' x2='" << px(x) << "' y2='"
         << py(y + half) << "' stroke='" << color << "' stroke-width='1.5'/>"
         << "<circle cx='" << px(x) << "' cy='" << py(y) << "' r='3.5' fill='" << color << "'/>\n";
  }

  void legend(const std::string& text, const char* color, bool dashed = false) {
    const double x = legend_origin_.first;
    const double y = legend_origin_.second + 16 * legend_rows_++;
    out_ << "<line x1='" << x << "' y1='" << y - 4 << "' x2='" << x + 24 << "' y2='" << y - 4
         << "' stroke='" << color << "' stroke-width='2'"
         << (dashed ? " stroke-dasharray='5,4'" : "") << "/><text x='" << x + 30 << "' y='" << y
         << "'>" << text << "</text>\n";
  }

  std::string str() const { return out_.str() + "</svg>\n"; }

 private:
  static constexpr double kW = 440, kH = 340, kL = 56, kR = 14, kT = 28, kB = 40;
  double px(double x) const { return kL + (x - x0_) / (x1_ - x0_) * (kW - kL - kR); }
  double py(double y) const { return kH - kB - (y - y0_) / (y1_ - y0_) * (kH - kT - kB); }

  double x0_, x1_, y0_, y1_;
  int legend_rows_ = 0;
  std::pair<double, double> legend_origin_{kL + 10, kT + 14};
  std::ostringstream out_;
};

void curveOf(SvgPlot& plot, const Cubic& theta, const char* color, bool dashed) {
  std::vector<double> xs, ys;
  for (int i = 0; i < kCurveSamples; ++i) {
    xs.push_back(i / double(kCurveSamples - 1));
    ys.push_back(evalCubic(theta, xs.back()));
  }
  plot.curve(xs, ys, color, dashed);
}

std::string curveDistance(const CurveDifference& d) {
  return fmt(d.value, "%.4f") + " (A " + fmt(d.A, "%.2f") + ", &rho; " + fmt(d.rho, "%.1f") + ")";
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

std::string sceneMixSection(const std::vector<SceneMixRow>& mix) {
  if (mix.empty()) return "";
  std::vector<std::vector<std::string>> rows;
  for (const SceneMixRow& r : mix) {
    rows.push_back({r.left_out, fmt(r.linear[0]), fmt(r.linear[2]), fmt(r.linear[4]),
                    curveDistance(r.vs_refit), curveDistance(r.vs_shipped)});
  }
  return "<h2>What the scene mix does: leave one scene out</h2>\n"
         "<p>The refit without each scene. The Monte Carlo SE says what another seed would move; "
         "this says what the choice of scenes moves, in the coefficients and in the curve "
         "G(A, &rho;) over A&isin;[0,1], &rho;&isin;[0.1,0.9].</p>\n" +
         table(
             {"left out", "a1", "b1", "c1", "max |&Delta;G| vs refit", "max |&Delta;G| vs shipped"},
             rows);
}

std::string errorTables(const ErrorTable& refit, const ErrorTable& shipped) {
  std::vector<std::vector<std::string>> rows;
  const auto add = [&](const std::string& label, const ErrorRow& r, const ErrorRow& s) {
    rows.push_back({label, fmt(r.rmse, "%.5f"), fmt(r.max_abs, "%.5f"), fmt(s.rmse, "%.5f"),
                    fmt(s.max_abs, "%.5f")});
  };
  for (std::size_t j = 0; j < refit.per_albedo.size(); ++j) {
    add("&rho; = " + refit.per_albedo[j].label, refit.per_albedo[j], shipped.per_albedo[j]);
  }
  for (std::size_t s = 0; s < refit.per_scene.size(); ++s) {
    add(refit.per_scene[s].label, refit.per_scene[s], shipped.per_scene[s]);
  }
  add("all", {"", 0, refit.rmse, refit.max_abs}, {"", 0, shipped.rmse, shipped.max_abs});
  return table({"", "refit RMSE", "refit max|e|", "shipped RMSE", "shipped max|e|"}, rows);
}

}  // namespace

void writeFitReport(const fs::path& dir, const FitReportInput& in) {
  ensureDirectory(dir);
  const SweepData& data = *in.data;
  const MultiBounceFit& fit = *in.fit;
  const std::size_t M = data.albedos.size();
  std::string figures;
  const auto figure = [&](const std::string& name, const SvgPlot& plot) {
    writeFileAtomically(dir / name, plot.str());
    figures += "<img src='" + name + "' alt='" + name + "'>\n";
  };

  figures += "<h2>Figure 6: A vs G per scene, every albedo, with the per-albedo cubics</h2>\n";
  for (const SweepScene& scene : data.scenes) {
    SvgPlot plot(0, 1, 0, 1, scene.name, "A (ambient occlusion)", "G (multi-bounce)");
    const std::size_t count = scene.end - scene.begin;
    const std::size_t stride = std::max<std::size_t>(1, count / kScatterPerScene);
    for (std::size_t j = 0; j < M; ++j) {
      std::vector<double> xs, ys;
      for (std::size_t i = scene.begin; i < scene.end; i += stride) {
        xs.push_back(data.full.A[i]);
        ys.push_back(data.full.G[j][i]);
      }
      plot.points(xs, ys, albedoColor(j, M));
    }
    for (std::size_t j = 0; j < M; ++j) curveOf(plot, fit.per_albedo[j].theta, "#000", false);
    plot.legendBottomRight(1);
    plot.legend("per-albedo cubic (all scenes)", "#000");
    figure("fig6_" + scene.name + ".svg", plot);
  }

  figures += "<h2>Figure 7: per-albedo cubics and their coefficients against &rho;</h2>\n";
  {
    SvgPlot plot(0, 1, 0, 1, "per-albedo cubic fits", "A", "G");
    plot.legendBottomRight(static_cast<int>(M));
    for (std::size_t j = M; j-- > 0;) {
      curveOf(plot, fit.per_albedo[j].theta, albedoColor(j, M), false);
      plot.legend("&#961; = " + fmt(data.albedos[j], "%.2f"), albedoColor(j, M));
    }
    figure("fig7_cubics.svg", plot);
  }
  const char* names[3] = {"a", "b", "c"};
  for (int q = 0; q < 3; ++q) {
    double lo = 1e9, hi = -1e9;
    for (const AlbedoFit& f : fit.per_albedo) {
      lo = std::min({lo, f.theta[q], f.uncorrected[q]});
      hi = std::max({hi, f.theta[q], f.uncorrected[q]});
    }
    for (double rho : {0.0, 1.0}) {
      for (const MultiBounceCoeffs* k : {&fit.linear.coeffs, &in.shipped}) {
        lo = std::min(lo, (*k)[2 * q] * rho + (*k)[2 * q + 1]);
        hi = std::max(hi, (*k)[2 * q] * rho + (*k)[2 * q + 1]);
      }
    }
    const double pad = 0.05 * (hi - lo + 1e-9);
    SvgPlot plot(0, 1, lo - pad, hi + pad, std::string(names[q]) + "(&#961;), bars &#177;2 SE",
                 "&#961; (albedo)", names[q]);
    for (const MultiBounceCoeffs* k : {&fit.linear.coeffs, &in.shipped}) {
      const bool shipped = k == &in.shipped;
      plot.curve({0.0, 1.0}, {(*k)[2 * q + 1], (*k)[2 * q] + (*k)[2 * q + 1]},
                 shipped ? "#888" : "#c0392b", shipped);
    }
    for (const AlbedoFit& f : fit.per_albedo) plot.errorBar(f.rho, f.theta[q], 2 * f.se[q], "#222");
    plot.legend("refit line", "#c0392b");
    plot.legend("shipped (paper) line", "#888", true);
    figure(std::string("fig7_") + names[q] + ".svg", plot);
  }

  figures += "<h2>Eq. 10: refit (solid) against shipped constants (dashed), G(A) per albedo</h2>\n";
  {
    SvgPlot plot(0, 1, 0, 1, "refit (solid) vs shipped (dashed)", "A", "G");
    plot.legendBottomRight(static_cast<int>(M));
    for (std::size_t j = M; j-- > 0;) {
      curveOf(plot, cubicAt(fit.linear.coeffs, data.albedos[j]), albedoColor(j, M), false);
      curveOf(plot, cubicAt(in.shipped, data.albedos[j]), albedoColor(j, M), true);
      plot.legend("&#961; = " + fmt(data.albedos[j], "%.2f"), albedoColor(j, M));
    }
    figure("refit_vs_shipped.svg", plot);
  }

  const char* coeff_names[6] = {"a1", "a0", "b1", "b0", "c1", "c0"};
  std::vector<std::vector<std::string>> coeff_rows;
  for (int i = 0; i < 6; ++i) {
    coeff_rows.push_back(
        {coeff_names[i], fmt(fit.linear.coeffs[i]), fmt(fit.linear.se[i], "%.5f"),
         fmt(in.shipped[i]), fmt((fit.linear.coeffs[i] - in.shipped[i]) / fit.linear.se[i], "%.1f"),
         fmt(fit.linear.eiv_bias[i], "%+.5f"),
         fmt(fit.eiv_corrected ? std::abs(fit.linear.eiv_bias[i] - fit.linear.eiv_bias_linear[i])
                               : std::abs(fit.linear.eiv_bias[i]),
             "%.5f"),
         fmt(fit.linear.misfit_se[i])});
  }
  std::vector<std::vector<std::string>> albedo_rows;
  for (const AlbedoFit& f : fit.per_albedo) {
    std::vector<std::string> row = {fmt(f.rho, "%.2f")};
    for (int q = 0; q < 3; ++q) {
      row.push_back(fmt(f.theta[q]) + " &#177; " + fmt(f.se[q], "%.5f"));
      row.push_back(fmt(f.eiv_bias[q], "%+.5f"));
    }
    row.push_back(fmt(f.rmse, "%.5f"));
    row.push_back(fmt(f.max_abs, "%.5f"));
    albedo_rows.push_back(row);
  }
  std::string scenes;
  for (const SweepScene& s : data.scenes) scenes += (scenes.empty() ? "" : ", ") + s.name;

  std::string html =
      "<!DOCTYPE html>\n<html><head><meta charset='utf-8'><title>gtbake fit report</title>\n"
      "<style>body{font-family:sans-serif;margin:24px;max-width:1400px}"
      "table{border-collapse:collapse;margin:8px 0 20px}"
      "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}"
      "th{background:#f3f3f3}img{margin:4px;border:1px solid #eee}</style></head><body>\n"
      "<h1>gtbake fit: multi-bounce Eq. 10</h1>\n<p>Sweep <code>" +
      relativePath(data.dir, dir) + "</code>: " + std::to_string(data.scenes.size()) + " scenes (" +
      scenes + "), " + std::to_string(data.points()) + " points, " + std::to_string(data.spp) +
      " spp, " + std::to_string(data.bounces) + " bounces. EIV correction " +
      (fit.eiv_corrected ? "on" : "off") + ". gtbake " + GTBAKE_VERSION +
      ". G = a(&rho;)A&sup3; &minus; b(&rho;)A&sup2; + c(&rho;)A.</p>\n"
      "<h2>Linear coefficients</h2>\n" +
      table({"coef", "refit", "SE (MC)", "shipped", "(refit&minus;shipped)/SE", "EIV bias",
             "bias left", "misfit SE"},
            coeff_rows) +
      "<p>SE (MC): Monte Carlo standard error (what a rerun with another seed moves). EIV bias: "
      "measured bias of the uncorrected fit from noise in A; bias left: what remains in the "
      "reported value. Misfit SE: OLS SE from the scatter of the 7 per-albedo coefficients about "
      "their line (model error of the linear-in-&rho; law, not noise). See docs/fit.md.</p>\n" +
      "<p>Largest |G<sub>refit</sub> &minus; G<sub>shipped</sub>| over A&isin;[0,1], "
      "&rho;&isin;[0.1,0.9]: <b>" +
      fmt(in.curve_difference.value, "%.5f") + "</b> at A = " + fmt(in.curve_difference.A, "%.3f") +
      ", &rho; = " + fmt(in.curve_difference.rho, "%.3f") + ".</p>\n<h2>Per-albedo cubics</h2>\n" +
      table({"&rho;", "a &#177; SE", "EIV bias a", "b &#177; SE", "EIV bias b", "c &#177; SE",
             "EIV bias c", "RMSE", "max|e|"},
            albedo_rows) +
      "<h2>Errors of G against the path-traced data</h2>\n" +
      errorTables(*in.refit_errors, *in.shipped_errors) +
      (in.scene_mix ? sceneMixSection(*in.scene_mix) : std::string()) + figures +
      "</body></html>\n";
  writeFileAtomically(dir / "index.html", html);
}

}  // namespace gtbake
