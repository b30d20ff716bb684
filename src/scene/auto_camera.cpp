#include "scene/auto_camera.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/math_constants.h"
#include "scene/mesh_builder.h"

namespace gtbake {

int parseAutoCamera(const std::string& text) {
  if (text == "auto") return kAutoViews;
  if (text.rfind("auto:", 0) != 0) return 0;
  const std::string count = text.substr(5);
  if (count.empty() || count.size() > 3 ||
      count.find_first_not_of("0123456789") != std::string::npos || std::stoi(count) < 1 ||
      std::stoi(count) > kMaxAutoViews) {
    throw Error("--camera " + text + ": expected auto or auto:K with K in [1, " +
                std::to_string(kMaxAutoViews) + "]");
  }
  return std::stoi(count);
}

std::vector<PerspectiveCamera> autoCameras(const Scene& scene, int views, double aspect) {
  if (scene.positions.empty()) throw Error("scene '" + scene.name + "' has no vertices to frame");
  Eigen::Vector3d lo = scene.positions.front().cast<double>(), hi = lo;
  for (const auto& p : scene.positions) {
    lo = lo.cwiseMin(p.cast<double>());
    hi = hi.cwiseMax(p.cast<double>());
  }
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double extent = std::max((hi - lo).norm(), 1e-6);
  const double tan_y = std::tan(0.5 * kAutoCameraFov), tan_x = tan_y * aspect;
  const double elevation = kAutoElevationDeg * kPi / 180.0;
  std::vector<PerspectiveCamera> cameras;
  for (int k = 0; k < views; ++k) {
    const double azimuth = kPi / 4.0 + 2.0 * kPi * k / views;
    const Eigen::Vector3d back(std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                               std::cos(elevation) * std::cos(azimuth));
    // Distance from the centre at which every corner q satisfies |x| ≤ (d − z) tan_x and
    // |y| ≤ (d − z) tan_y in the camera frame (z along `back`, towards the camera).
    const PerspectiveCamera frame = lookAt(centre + back, centre, Eigen::Vector3d::UnitY(), 1.0);
    double distance = 1e-3 * extent;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d q(c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(),
                              c & 4 ? hi.z() : lo.z());
      const Eigen::Vector3d local = frame.basis.transpose() * (q - centre);
      distance = std::max({distance, local.z() + std::abs(local.x()) / tan_x,
                           local.z() + std::abs(local.y()) / tan_y});
    }
    cameras.push_back(
        lookAt(centre + distance * back, centre, Eigen::Vector3d::UnitY(), kAutoCameraFov));
  }
  return cameras;
}

}  // namespace gtbake
