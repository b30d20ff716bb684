#include <algorithm>

#include "common/text_escape.h"
#include "common/text_format.h"
#include "plot/svg_plot.h"
#include "tune/tune_outputs.h"

namespace gtbake {

namespace {

constexpr const char* kPaperColor = "#d62728";
constexpr const char* kProfileColor = "#1f77b4";

std::string axisLabel(const SettingGrid& g) {
  const bool metres = g.key == "radius" || g.key == "thickness";
  const std::string name = g.key + (metres ? " (m)" : "");
  return g.log_axis ? "log10 " + name : name;
}

// The optimum as a point on its curve with its interval as a horizontal bar.
void markOptimum(SvgPlot& plot, const SceneInterval& o, const std::vector<double>& x,
                 const std::vector<double>& y, const char* color) {
  std::size_t k = 0;
  while (k + 1 < x.size() && x[k + 1] < o.z) ++k;
  const std::size_t k1 = std::min(k + 1, x.size() - 1);
  const double w = k1 == k ? 0.0 : std::clamp((o.z - x[k]) / (x[k1] - x[k]), 0.0, 1.0);
  const double at = (1.0 - w) * y[k] + w * y[k1];
  if (!o.at_bound) {
    plot.curve({std::max(o.low, x.front()), std::min(o.high, x.back())}, {at, at}, color, false,
               3.0);
  }
  plot.points({o.z}, {at}, color, 4.0);
}

std::string settingPlot(const SettingResult& r) {
  std::vector<double> x, paper, profile, held_out;
  for (const GridValueScore& g : r.scores) {
    x.push_back(axisValue(r.grid, g.value));
    paper.push_back(g.paper_rmse);
    profile.push_back(g.profile_rmse);
    held_out.push_back(g.held_out_rmse);
  }
  double lo = profile.front(), hi = paper.front();
  for (const auto* curve : {&paper, &profile, &held_out}) {
    lo = std::min(lo, *std::min_element(curve->begin(), curve->end()));
    hi = std::max(hi, *std::max_element(curve->begin(), curve->end()));
  }
  const double pad = 0.05 * std::max(hi - lo, 1e-6);
  SvgPlot plot(x.front(), x.back(), lo - pad, hi + pad,
               escapeHtml(std::string(r.grid.name()) + ": " + r.grid.key), axisLabel(r.grid),
               "RMSE of G");
  plot.legendBelow(3);  // the curves cross every corner of the axes
  plot.curve(x, paper, kPaperColor);
  plot.points(x, paper, kPaperColor, 2.5);
  plot.curve(x, profile, kProfileColor);
  plot.points(x, profile, kProfileColor, 2.5);
  plot.curve(x, held_out, kProfileColor, true);
  markOptimum(plot, r.paper, x, paper, kPaperColor);
  markOptimum(plot, r.profile, x, profile, kProfileColor);
  plot.legend("paper's constants on A&#770;", kPaperColor);
  plot.legend("profile refit (in sample)", kProfileColor);
  plot.legend("profile, held out by scene", kProfileColor, true);
  return plot.str();
}

// At a bound the interval says nothing; how many replicas are there too and the limit do.
std::string optimumCell(const SettingResult& r, const SceneInterval& o) {
  const OptimumPlace place = optimumPlace(r, o);
  std::string cell = escapeHtml(optimumSummary(r, o));
  if (place.status != OptimumStatus::kInterior) {
    cell += "<br>" + std::string(statusName(place.status)) + ": " + escapeHtml(place.limit.reason);
  }
  return cell;
}

}  // namespace

std::string tuneReportHtml(const TuneAnalysis& a) {
  std::string html =
      "<!doctype html><html><head><meta charset='utf-8'><title>gtbake tune</title>"
      "<style>body{font:14px sans-serif;margin:2em}td,th{padding:2px 8px;border:1px solid #ccc}"
      "table{border-collapse:collapse}svg{margin:6px}</style></head><body>\n"
      "<h1>Screen-space settings against path-traced G (docs/tune.md)</h1>\n<p>RMSE of G = "
      "Eq. 10 on each estimator's A&#770; over " +
      std::to_string(a.points) + " pixels &times; " + std::to_string(a.albedos.size()) +
      " albedos of " + std::to_string(a.clusters.size()) +
      " scenes; one setting at a time, the others at their defaults. Bars: the optimum's 95 % "
      "scene-level interval (delete-one-scene jackknife), clipped to the searched grid; an optimum "
      "at a grid end after widening is a bound, not a best "
      "value.</p>\n<table><tr><th>estimator</th>"
      "<th>setting</th><th>default</th><th>paper: optimum [interval]</th><th>profile: optimum "
      "[interval]</th></tr>\n";
  for (const SettingResult& r : a.settings) {
    html += "<tr><td>" + escapeHtml(r.grid.name()) + "</td><td>" + escapeHtml(r.grid.key) +
            "</td><td>" + formatNumber(r.grid.default_value, "%.3g") + "</td><td>" +
            optimumCell(r, r.paper) + "</td><td>" + optimumCell(r, r.profile) + "</td></tr>\n";
  }
  html += "</table>\n<div>\n";
  for (const SettingResult& r : a.settings) html += settingPlot(r);
  return html + "</div>\n</body></html>\n";
}

}  // namespace gtbake
