// The pictures of `gtbake screen-ao`: per image an EXR of every estimator's Â and b̂, PNGs (the
// ray-traced A, each Â, each signed difference Â − A) and one HTML page showing them
// (docs/screen_ao.md, "Outputs").
#pragma once

#include <string>
#include <vector>

#include "common/output_set.h"
#include "screen_ao/estimate.h"
#include "screen_ao/gbuffer.h"
#include "screen_ao/screen_ao_json.h"

namespace gtbake {

// Channels <estimator>.A, <estimator>.BNX/BNY/BNZ (world space) and mask.
std::string screenAoExr(const SweepImage& image, const std::vector<std::string>& estimators,
                        const std::vector<AoEstimate>& estimates);

// Signed difference d ∈ [−range, range] as RGB: blue (negative) – white (0) – red (positive).
std::vector<std::uint8_t> divergingRgb8(const std::vector<float>& d, float range);

// Stages <image>_A.png, <image>_<estimator>.png, <image>_<estimator>_diff.png for every image
// and screen_ao.html. estimates[e][k]: estimator e on image k.
void stageReport(OutputSet* output, const std::vector<SweepImage>& images,
                 const std::vector<EstimatorRun>& runs,
                 const std::vector<std::vector<AoEstimate>>& estimates);

}  // namespace gtbake
