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

void useScreenEstimate(SweepData* data, const AoInput& input) {
  if (input.rayTraced()) return;
  const ScreenEstimateSet set(input);
  for (const SweepScene& scene : data->scenes) {
    const ImageEstimate image = set.read(scene.name, data->dir, false);
    std::vector<double> estimate;
    for (std::size_t p = 0; p < image.mask.size(); ++p) {
      if (image.mask[p]) estimate.push_back(image.A[p]);
    }
    if (estimate.size() != scene.end - scene.begin) {
      throw Error(image.file + ": its mask has " + std::to_string(estimate.size()) +
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
