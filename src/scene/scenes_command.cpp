// `gtbake scenes`: builds the seven scene types and writes them as glTF (docs/scenes.md "The seven
// scene types", docs/index.md "Pipeline").
#include "scene/scenes_command.h"

#include <Eigen/Core>
#include <cstdio>

#include "common/atomic_file.h"
#include "common/progress.h"
#include "scene/procedural_scenes.h"
#include "scene/scene.h"

namespace gtbake {

std::vector<std::filesystem::path> runScenes(const ScenesOptions& options) {
  ensureDirectory(options.out);
  cleanStaleTemporaries(options.out);  // left by a killed run (atomic_file.h)
  const auto& names = sceneTypeNames();
  std::vector<std::filesystem::path> written;
  Progress progress("scenes", names.size(), options.progress);
  for (const std::string& name : names) {
    const Scene scene = makeSceneType(name, options.seed);
    const std::filesystem::path path = options.out / (name + ".gltf");
    writeGltfScene(path, scene);
    written.push_back(path);
    progress.add(1);
    // Bounding box of the geometry near the features (|x|, |z| < 100 m), and of everything.
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e30f), hi = -lo;
    Eigen::Vector3f near_lo = lo, near_hi = hi;
    for (const auto& p : scene.positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      if (std::abs(p.x()) < 100.0f && std::abs(p.z()) < 100.0f) {
        near_lo = near_lo.cwiseMin(p);
        near_hi = near_hi.cwiseMax(p);
      }
    }
    std::printf(
        "%-8s %7zu triangles %7zu vertices  bbox [%g %g %g]..[%g %g %g]  feature heights "
        "[%.3g, %.3g]  -> %s\n",
        name.c_str(), scene.triangles.size(), scene.positions.size(), lo.x(), lo.y(), lo.z(),
        hi.x(), hi.y(), hi.z(), near_lo.y(), near_hi.y(), path.string().c_str());
  }
  progress.finish();
  return written;
}

}  // namespace gtbake
