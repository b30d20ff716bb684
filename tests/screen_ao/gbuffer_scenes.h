// Height fields whose occluders are all in view, traced with the sweep's own walks into the
// G-buffer and ray-traced answers that `gtbake screen-ao` reads (docs/screen_ao.md, "Tests").
#pragma once

#include <cstdint>

#include "scene/scene.h"
#include "screen_ao/gbuffer.h"

namespace gtbake::test {

// An infinite V-groove along z, half-width w and depth d (y = −d·max(0, 1 − |x|/w)), in a ground
// 10 km wide; camera straight down from height `height` (yfov 0.5).
Scene grooveField(double w, double d, double height);
// A floor y = 0 for x < 0 and z < 0, rising within 1 cm to a plateau of height h (two walls and
// their corner); camera above the floor looking down past the corner.
Scene cornerField(double h);
// A plane y = 0 10 km wide, camera at height 1 looking down at 45°.
Scene openField();

// Traces `scene` at width × height with `spp` walks, one bounce, A_R at `radius`, seed `seed`,
// into the SweepImage the command would read.
SweepImage traceImage(const Scene& scene, int width, int height, int spp, double radius,
                      std::uint64_t seed);

}  // namespace gtbake::test
