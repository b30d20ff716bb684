// Equation 10 on what an engine's pass computes: the sweep's points with A replaced by a
// screen-space estimator's Â (docs/profiles.md §1).
//
// A `gtbake screen-ao` output set holds, per swept image, `<image>.exr` with the channel
// `<estimator>.A` and the sweep's own mask. useScreenEstimate() puts Â in place of the ray-traced
// A of every point — in the full estimate and in both half-sample estimates, since Â is a
// deterministic function of the G-buffer and carries no Monte Carlo noise of its own — and leaves
// G (the path-traced target) as it is. Everything downstream (the two-stage fit, the jackknives,
// the band, the floor, the error tables) then reads Â as its regressor.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "fit/sweep_data.h"
#include "screen_ao/screen_ao_set.h"

namespace gtbake {

// Replaces A by the estimator's Â in `data` (loaded from the sweep that screen-ao read). Every
// file is verified against the screen-ao manifest; an image the sweep has and screen-ao lacks, a
// mask that differs from the sweep's, an estimator not in the set or a value outside [0, 1] (by
// more than float rounding, 1e-5, which is clamped) is a one-line gtbake::Error.
void useScreenEstimate(SweepData* data, const AoInput& input);

}  // namespace gtbake
