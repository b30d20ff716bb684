// `gtbake scenes`: builds the corpus (or the seven classic scenes) and writes them as glTF
// (docs/scenes.md, docs/index.md "Pipeline").
#include "scene/scenes_command.h"

#include <Eigen/Core>
#include <cstdio>

#include "common/error.h"
#include "common/output_set.h"
#include "common/progress.h"
#include "scene/procedural_scenes.h"
#include "scene/scene.h"
#include "scene/scene_corpus.h"

namespace gtbake {

namespace {
constexpr int kMaxVariants = 1000;  // names stay short; more variants than that is a mistake
}  // namespace

std::vector<std::filesystem::path> runScenes(const ScenesOptions& options) {
  if (options.variants < 1 || options.variants > kMaxVariants) {
    throw Error("--variants must be in [1, " + std::to_string(kMaxVariants) + "]");
  }
  // Every scene's .gltf and .bin switch in as one set (output_set.h): a failed run keeps the
  // previous corpus whole.
  OutputSet set(options.out, "scenes");
  std::vector<std::pair<std::string, int>> list;  // (type, variant); variant −1: classic
  for (const std::string& type : options.classic ? sceneTypeNames() : corpusTypeNames()) {
    for (int v = 0; v < (options.classic ? 1 : options.variants); ++v) {
      list.emplace_back(type, options.classic ? -1 : v);
    }
  }
  std::vector<std::filesystem::path> written;
  Progress progress("scenes", list.size(), options.progress);
  for (const auto& [type, variant] : list) {
    const Scene scene = variant < 0 ? makeSceneType(type, options.seed)
                                    : makeCorpusScene(type, variant, options.seed);
    const std::string& name = scene.name;
    const std::filesystem::path path = options.out / (name + ".gltf");
    const GltfFiles files = encodeGltfScene(name, scene);
    set.add(name + ".bin", files.bin);
    set.add(name + ".gltf", files.gltf);
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
        "%-13s %7zu triangles %7zu vertices  bbox [%g %g %g]..[%g %g %g]  feature heights "
        "[%.3g, %.3g]  -> %s\n",
        name.c_str(), scene.triangles.size(), scene.positions.size(), lo.x(), lo.y(), lo.z(),
        hi.x(), hi.y(), hi.z(), near_lo.y(), near_hi.y(), path.string().c_str());
  }
  set.setSettings(
      {{"seed", options.seed}, {"variants", options.variants}, {"classic", options.classic}});
  set.commit();
  progress.finish();
  return written;
}

}  // namespace gtbake
