#include "fit/screen_estimate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/image_io.h"
#include "common/input_limits.h"
#include "common/output_set.h"
#include "common/text_format.h"

namespace gtbake {

namespace {

// screen_ao.json's images by name: the EXR file of each and the estimators it holds.
struct ScreenAoSet {
  OutputManifest manifest;
  std::map<std::string, std::string> files;  // image name -> EXR file name
};

ScreenAoSet readScreenAoSet(const std::filesystem::path& dir, const std::string& estimator) {
  ScreenAoSet set;
  set.manifest = readOutputSet(dir, "screen_ao");
  const std::string where = (dir / "screen_ao.json").string();
  const nlohmann::json doc = parseJsonText(set.manifest.readVerified("screen_ao.json"), where);
  if (!doc.is_object() || !doc.contains("images") || !doc["images"].is_array() ||
      !doc.contains("estimators") || !doc["estimators"].is_object()) {
    throw Error(where + ": not a screen-ao result (needs 'images' and 'estimators')");
  }
  if (!doc["estimators"].contains(estimator)) {
    throw Error(where + " has no estimator '" + estimator + "' (rerun `gtbake screen-ao` with it)");
  }
  for (const nlohmann::json& image : doc["images"]) {
    if (!image.is_object() || !image.contains("name") || !image["name"].is_string() ||
        !image.contains("file") || !image["file"].is_string()) {
      throw Error(where + ": every image needs a name and a file");
    }
    set.files[image["name"].get<std::string>()] = image["file"].get<std::string>();
  }
  return set;
}

// The unmasked pixels' Â of one image, in the sweep's point order (row-major, mask > 0.5).
std::vector<double> unmaskedEstimate(const ExrImage& image, const std::string& file,
                                     const std::string& estimator) {
  const std::vector<float>& mask = image.channel("mask", file);
  const std::vector<float>& a = image.channel(estimator + ".A", file);
  std::vector<double> out;
  for (std::size_t p = 0; p < mask.size(); ++p) {
    if (!(mask[p] > 0.5f)) continue;
    if (!(a[p] >= -kEstimateRounding && a[p] <= 1.0f + kEstimateRounding)) {
      throw Error(file + ": " + estimator + ".A = " + formatNumber(a[p], "%.9g") +
                  " is outside [0, 1] at an unmasked pixel (" +
                  std::to_string(p % static_cast<std::size_t>(image.width)) + ", " +
                  std::to_string(p / static_cast<std::size_t>(image.width)) + ")");
    }
    out.push_back(std::clamp(static_cast<double>(a[p]), 0.0, 1.0));
  }
  return out;
}

}  // namespace

void useScreenEstimate(SweepData* data, const AoInput& input) {
  if (input.rayTraced()) return;
  const ScreenAoSet set = readScreenAoSet(input.screen_ao, input.estimator);
  for (const SweepScene& scene : data->scenes) {
    const auto found = set.files.find(scene.name);
    if (found == set.files.end()) {
      throw Error((input.screen_ao / "screen_ao.json").string() + " has no image '" + scene.name +
                  "' of the sweep " + data->dir.string() + " (rerun `gtbake screen-ao` on it)");
    }
    const std::string file = (input.screen_ao / found->second).string();
    const ExrImage image = decodeExr(set.manifest.readVerified(found->second), file);
    const std::vector<double> estimate = unmaskedEstimate(image, file, input.estimator);
    if (estimate.size() != scene.end - scene.begin) {
      throw Error(file + ": its mask has " + std::to_string(estimate.size()) +
                  " pixels, the sweep's image '" + scene.name + "' " +
                  std::to_string(scene.end - scene.begin) +
                  " (screen-ao was run on another sweep; rerun it)");
    }
    for (std::size_t k = 0; k < estimate.size(); ++k) {
      const std::size_t i = scene.begin + k;
      data->full.A[i] = data->half[0].A[i] = data->half[1].A[i] = estimate[k];
    }
  }
}

}  // namespace gtbake
