#include <cstdio>
#include <sstream>

#include "common/text_escape.h"
#include "common/text_format.h"
#include "gtbake_version.h"
#include "lighting/lighting_command.h"

namespace gtbake {

namespace {

using ojson = nlohmann::ordered_json;

ojson statsJson(const LightingErrors& s) {
  ojson j;
  j["pixels"] = s.pixels;
  j["rmse"] = s.rmse();
  j["bias"] = s.bias();
  j["glow_share"] = s.glowShare();
  return j;
}

ojson modelJson(const LightingAnalysis& a, const ModelErrors& m) {
  ojson j;
  j["per_albedo"] = ojson::array();
  for (std::size_t k = 0; k < m.albedo.size(); ++k) {
    ojson e = statsJson(m.albedo[k]);
    e["albedo"] = a.albedos[k];
    j["per_albedo"].push_back(e);
  }
  if (m.model == "refit") return j;  // per albedo only (docs/lighting.md §3)
  j["per_a_bin"] = ojson::array();
  for (int b = 0; b < kLightingABins; ++b) {
    ojson e = statsJson(m.a_bins[b]);
    e["a_low"] = static_cast<double>(b) / kLightingABins;
    e["a_high"] = static_cast<double>(b + 1) / kLightingABins;
    j["per_a_bin"].push_back(e);
  }
  j["per_type"] = ojson::array();
  for (std::size_t t = 0; t < m.types.size(); ++t) {
    ojson e = statsJson(m.types[t]);
    e["type"] = a.types[t];
    j["per_type"].push_back(e);
  }
  return j;
}

ojson bandScoreJson(const BandScore& s) {
  ojson j;
  j["consistent"] = s.consistent;
  j["max_ratio"] = s.max_ratio.value;
  j["at_A"] = s.max_ratio.A;
  j["at_albedo"] = s.max_ratio.rho;
  j["threshold"] = s.threshold;
  j["verdict"] = s.verdict;
  return j;
}

ojson refitJson(const EnvironmentRefit& r) {
  ojson j;
  j["available"] = r.available;
  j["points"] = r.points;
  if (!r.message.empty()) j["message"] = r.message;
  if (!r.available) return j;
  j["coefficients"] = r.coeffs;
  j["se"] = r.se;
  j["scene_band"] = r.band;
  if (!r.band) return j;
  j["band_max"] = r.band_max;
  j["paper"] = bandScoreJson(r.paper);
  if (r.fit) j["fit"] = bandScoreJson(*r.fit);
  return j;
}

}  // namespace

ojson lightingJson(const LightingAnalysis& a, const std::string& sweep, const std::string& fit) {
  ojson j;
  j["gtbake_version"] = GTBAKE_VERSION;
  j["sweep"] = sweep;
  j["fit"] = fit.empty() ? ojson(nullptr) : ojson(fit);
  j["glow_share_threshold"] = kGlowShare;
  j["refit_min_open"] = kRefitMinOpen;
  j["reference_albedo"] = a.albedos[a.reference];
  j["pixels"] = a.pixels;
  j["environments"] = ojson::array();
  for (const EnvironmentResult& e : a.environments) {
    ojson env;
    env["name"] = e.environment.name;
    env["sh"] = e.environment.sh;
    env["mean_open"] = e.mean_open;
    env["models"] = ojson::object();
    for (const ModelErrors& m : e.models) env["models"][m.model] = modelJson(a, m);
    env["refit"] = refitJson(e.refit);
    env["images"] = ojson::array();
    for (const auto& image : e.images) env["images"].push_back(image.first);
    j["environments"].push_back(env);
  }
  return j;
}

std::string lightingReportHtml(const LightingAnalysis& a) {
  std::ostringstream h;
  h << "<!doctype html><html><head><meta charset=\"utf-8\"><title>gtbake lighting</title></head>"
       "<body><h1>Equation 10 under environments</h1><p>Errors of open irradiance × G(A, ρ) "
       "against the true G(ρ, L), in units of an open floor's G, at ρ = "
    << formatNumber(a.albedos[a.reference], "%.2f") << " (docs/lighting.md §3).</p>";
  for (const EnvironmentResult& e : a.environments) {
    h << "<h2>" << escapeHtml(e.environment.name) << "</h2><table border=\"1\"><tr><th>model</th>"
      << "<th>RMSE</th><th>bias</th><th>glowing pixels</th></tr>";
    for (const ModelErrors& m : e.models) {
      const LightingErrors& s = m.albedo[a.reference];
      h << "<tr><td>" << escapeHtml(m.model) << "</td><td>" << formatNumber(s.rmse()) << "</td><td>"
        << formatNumber(s.bias()) << "</td><td>" << formatNumber(100.0 * s.glowShare(), "%.1f")
        << " %</td></tr>";
    }
    h << "</table><p>Refit: "
      << escapeHtml(e.refit.band ? e.refit.paper.verdict
                                 : (e.refit.available ? e.refit.message : "not available"))
      << "</p>";
    for (const auto& image : e.images) {
      h << "<figure><img src=\"" << escapeHtml(image.first) << "\"><figcaption>"
        << escapeHtml(image.first) << ": paper − truth, −0.5 … 0.5</figcaption></figure>";
    }
  }
  h << "</body></html>\n";
  return h.str();
}

void printLightingSummary(const LightingAnalysis& a) {
  std::printf("%-12s %-16s %8s %8s %8s\n", "environment", "model", "RMSE", "bias", "glow %");
  for (const EnvironmentResult& e : a.environments) {
    for (const ModelErrors& m : e.models) {
      const LightingErrors& s = m.albedo[a.reference];
      std::printf("%-12s %-16s %8.4f %8.4f %8.1f\n", e.environment.name.c_str(), m.model.c_str(),
                  s.rmse(), s.bias(), 100.0 * s.glowShare());
    }
  }
}

}  // namespace gtbake
