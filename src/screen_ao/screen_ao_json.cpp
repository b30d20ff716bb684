#include "screen_ao/screen_ao_json.h"

namespace gtbake {

namespace {

nlohmann::ordered_json orNull(std::size_t pixels, double value) {
  return pixels > 0 ? nlohmann::ordered_json(value) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json referenceSettingsJson(const GtaoReferenceSettings& s) {
  return {{"radius", s.radius},
          {"slices", s.slices},
          {"refine_tolerance", s.refine_tolerance},
          {"refine_levels", s.refine_levels}};
}

}  // namespace

nlohmann::ordered_json errorSummaryJson(const ErrorSummary& e) {
  nlohmann::ordered_json j;
  j["A_lo"] = e.lo;
  j["A_hi"] = e.hi;
  j["pixels"] = e.pixels;
  j["bias"] = orNull(e.pixels, e.bias);
  j["rmse"] = orNull(e.pixels, e.rmse);
  j["pixels_at_radius"] = e.pixels_at_radius;
  j["bias_at_radius"] = orNull(e.pixels_at_radius, e.bias_at_radius);
  j["rmse_at_radius"] = orNull(e.pixels_at_radius, e.rmse_at_radius);
  j["bent_mean_deg"] = orNull(e.pixels, e.bent_mean_deg);
  j["bent_p95_deg"] = orNull(e.pixels, e.bent_p95_deg);
  return j;
}

nlohmann::ordered_json estimatorJson(const EstimatorRun& run) {
  nlohmann::ordered_json j;
  j["settings"] = run.settings;
  j["radius_channel"] = run.radius_channel.empty() ? nlohmann::ordered_json(nullptr)
                                                   : nlohmann::ordered_json(run.radius_channel);
  j["seconds"] = run.seconds;
  j["megapixels"] = run.megapixels;
  j["seconds_per_megapixel"] = run.megapixels > 0.0 ? run.seconds / run.megapixels : 0.0;
  nlohmann::ordered_json groups = nlohmann::ordered_json::object();
  for (const GroupErrors& g : run.errors) {
    nlohmann::ordered_json bins = nlohmann::ordered_json::array();
    for (const ErrorSummary& b : g.bins) bins.push_back(errorSummaryJson(b));
    groups[g.group] = {{"all", errorSummaryJson(g.all)}, {"bins", std::move(bins)}};
  }
  j["scenes"] = std::move(groups);
  return j;
}

nlohmann::ordered_json convergenceJson(const ReferenceConvergence& c) {
  nlohmann::ordered_json j;
  j["settings"] = referenceSettingsJson(c.settings);
  j["doubled"] = referenceSettingsJson(c.doubled);
  j["pixel_stride"] = kConvergenceStride;
  j["pixels"] = c.pixels;
  j["rms_change"] = c.rms_change;
  j["max_change"] = c.max_change;
  j["bar"] = kConvergenceBar;
  j["converged"] = c.rms_change < kConvergenceBar;
  return j;
}

}  // namespace gtbake
