// Automatic cameras: K views framing the bounding box of a scene that has no camera of its own
// (docs/scenes.md, "Automatic cameras").
//
// View k of K looks at the centre of the axis-aligned bounding box of every vertex from azimuth
// φ_k = 45° + 360° k / K about +Y (φ = 0 is +Z, φ = 90° is +X) and elevation 35° above the
// horizontal plane, with +Y up in the image; the distance is the smallest at which all eight box
// corners project inside the image (vertical field of view kAutoCameraFov, aspect width/height).
// The box is then in front of the camera and the camera outside it.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace gtbake {

inline constexpr int kAutoViews = 4;           // views of `--camera auto`
inline constexpr int kMaxAutoViews = 64;       // more views of one scene add no new geometry
inline constexpr double kAutoCameraFov = 0.8;  // rad, as the procedural scenes
inline constexpr double kAutoElevationDeg = 35.0;

// K for "auto" (kAutoViews) or "auto:K" (1 ≤ K ≤ kMaxAutoViews); 0 for any other text, which
// names a camera of the file. Throws gtbake::Error for a malformed "auto:…".
int parseAutoCamera(const std::string& text);

// The K views of `scene` (its positions must not be empty) for an image of aspect ratio
// width/height.
std::vector<PerspectiveCamera> autoCameras(const Scene& scene, int views, double aspect);

}  // namespace gtbake
