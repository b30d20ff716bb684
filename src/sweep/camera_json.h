// The camera a sweep traces with, as the "camera" object of each sweep.json views[] entry, so a
// screen-space pass can rebuild view-space positions from the Z channel (docs/sweep.md,
// "G-buffer").
#pragma once

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace gtbake {

// {"model": "perspective", "position": [x, y, z], "right": [...], "up": [...], "backward": [...],
//  "yfov": radians}: world-space pose (the basis columns of PerspectiveCamera) and intrinsics;
// the aspect ratio is the entry's width/height and pixel (i, j) looks along
// sx·right + sy·up − backward with sx, sy as cameraRay (embree_tracer.h).
nlohmann::ordered_json cameraJson(const PerspectiveCamera& camera);

// The inverse of cameraJson. Throws gtbake::Error "<where>: ..." on a missing or malformed field
// (non-finite numbers, a basis that is not orthonormal within 1e-6, yfov outside (0, π)).
PerspectiveCamera cameraFromJson(const nlohmann::json& json, const std::string& where);

}  // namespace gtbake
