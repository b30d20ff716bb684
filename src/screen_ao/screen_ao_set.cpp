#include "screen_ao/screen_ao_set.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/image_io.h"
#include "common/input_limits.h"
#include "common/text_format.h"

namespace gtbake {

std::string pixelText(std::size_t p, int width) {
  return "(" + std::to_string(p % static_cast<std::size_t>(width)) + ", " +
         std::to_string(p / static_cast<std::size_t>(width)) + ")";
}

std::optional<float> clampedEstimate(float a) {
  if (!(a >= -kEstimateRounding && a <= 1.0f + kEstimateRounding)) return std::nullopt;
  return std::clamp(a, 0.0f, 1.0f);
}

ScreenEstimateSet::ScreenEstimateSet(const AoInput& input) : input_(input) {
  manifest_ = readOutputSet(input.screen_ao, "screen_ao");
  const std::string where = (input.screen_ao / "screen_ao.json").string();
  const nlohmann::json doc = parseJsonText(manifest_.readVerified("screen_ao.json"), where);
  if (!doc.is_object() || !doc.contains("images") || !doc["images"].is_array() ||
      !doc.contains("estimators") || !doc["estimators"].is_object()) {
    throw Error(where + ": not a screen-ao result (needs 'images' and 'estimators')");
  }
  if (!doc["estimators"].contains(input.estimator)) {
    throw Error(where + " has no estimator '" + input.estimator +
                "' (rerun `gtbake screen-ao` with it)");
  }
  const nlohmann::json* settings = nullptr;
  if (doc.contains("settings") && doc["settings"].is_object() &&
      doc["settings"].contains(input.estimator) && doc["settings"][input.estimator].is_object()) {
    settings = &doc["settings"][input.estimator];
  }
  if (settings != nullptr && settings->contains("radius") && (*settings)["radius"].is_number() &&
      (*settings)["radius"].get<double>() > 0.0) {
    radius_ = (*settings)["radius"].get<double>();
  }
  for (const nlohmann::json& image : doc["images"]) {
    if (!image.is_object() || !image.contains("name") || !image["name"].is_string() ||
        !image.contains("file") || !image["file"].is_string()) {
      throw Error(where + ": every image needs a name and a file");
    }
    const std::string name = image["name"].get<std::string>();
    if (!files_.emplace(name, image["file"].get<std::string>()).second) {
      throw Error(where + ": image '" + name + "' is listed twice");
    }
  }
}

double ScreenEstimateSet::radius() const {
  if (!radius_) {
    throw Error((input_.screen_ao / "screen_ao.json").string() + ": settings." + input_.estimator +
                ".radius must be a positive number (the radius of its near-field truth)");
  }
  return *radius_;
}

std::optional<double> truthRadius(const AoInput& input) {
  if (input.rayTraced() || input.unbounded_truth) return std::nullopt;
  return ScreenEstimateSet(input).radius();
}

ImageEstimate ScreenEstimateSet::read(const std::string& name, const std::filesystem::path& sweep,
                                      bool with_bent) const {
  const auto found = files_.find(name);
  if (found == files_.end()) {
    throw Error((input_.screen_ao / "screen_ao.json").string() + " has no image '" + name +
                "' of the sweep " + sweep.string() + " (rerun `gtbake screen-ao` on it)");
  }
  ImageEstimate e;
  e.file = (input_.screen_ao / found->second).string();
  const std::shared_ptr<const ExrImage> shared = readVerifiedExr(manifest_, found->second, e.file);
  const ExrImage& image = *shared;
  e.width = image.width;
  e.height = image.height;
  const std::string& est = input_.estimator;
  const std::vector<float>& mask = image.channel("mask", e.file);
  e.A = image.channel(est + ".A", e.file);
  if (with_bent) {
    const std::vector<float>* bn[3] = {&image.channel(est + ".BNX", e.file),
                                       &image.channel(est + ".BNY", e.file),
                                       &image.channel(est + ".BNZ", e.file)};
    e.bent.resize(3 * mask.size());
    for (std::size_t p = 0; p < mask.size(); ++p) {
      for (int c = 0; c < 3; ++c) e.bent[3 * p + c] = (*bn[c])[p];
    }
  }
  e.mask.resize(mask.size());
  for (std::size_t p = 0; p < mask.size(); ++p) {
    e.mask[p] = mask[p] > 0.5f ? 1 : 0;
    if (!e.mask[p]) continue;
    const std::optional<float> a = clampedEstimate(e.A[p]);
    if (!a) {
      throw Error(e.file + ": " + est + ".A = " + formatNumber(e.A[p], "%.9g") +
                  " is outside [0, 1] at an unmasked pixel " + pixelText(p, e.width));
    }
    e.A[p] = *a;
    if (!with_bent) continue;
    const float* b = &e.bent[3 * p];
    const float length = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    if (!(std::abs(length - 1.0f) <= kBentUnitTolerance)) {
      throw Error(e.file + ": " + est + ".BN is not a unit vector at an unmasked pixel " +
                  pixelText(p, e.width) + " (length " + formatNumber(length, "%.6g") + ")");
    }
  }
  return e;
}

}  // namespace gtbake
