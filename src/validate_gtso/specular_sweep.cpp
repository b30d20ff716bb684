#include "validate_gtso/specular_sweep.h"

#include <cmath>
#include <utility>

#include "common/error.h"
#include "common/image_io.h"
#include "common/provenance.h"
#include "sweep/specular_occlusion.h"
#include "sweep/sweep_set.h"

namespace gtbake {

namespace {

namespace fs = std::filesystem;

constexpr const char* kNoSpecular =
    "has no specular channels (S010 ...): trace it with gtbake sweep --specular-roughness LIST "
    "(the default traces 0.1,0.25,0.4,0.6,0.8; 'none' turns them off)";

const std::vector<float>& need(const ExrImage& image, const std::string& name,
                               const std::string& file, const char* hint) {
  const auto it = image.channels.find(name);
  if (it == image.channels.end()) throw Error(file + ": no channel " + name + " " + hint);
  return it->second;
}

// The values read are checked where they are read, even under a resealed manifest
// (docs/limits.md §Values): A and every S estimate in [0, 1] at unmasked pixels, vectors finite.
void checkRanges(const SpecularScene& scene, const std::string& where) {
  const auto fail = [&](const char* what, std::size_t p) {
    throw Error(where + ": " + what + " at pixel (" + std::to_string(p % scene.width) + ", " +
                std::to_string(p / scene.width) + ") (rerun `gtbake sweep`)");
  };
  const auto unit = [](float v) { return v >= 0.0f && v <= 1.0f; };
  for (std::size_t p = 0; p < scene.mask.size(); ++p) {
    if (scene.mask[p] == 0) continue;
    if (!unit(scene.A[p])) fail("A outside [0, 1]", p);
    for (std::size_t j = 0; j < scene.S.size(); ++j) {
      if (!unit(scene.S[j][p]) || !unit(scene.H0[j][p]) || !unit(scene.H1[j][p])) {
        fail("an S estimate outside [0, 1]", p);
      }
    }
    for (const std::vector<float>* v : {&scene.normal, &scene.view, &scene.bent}) {
      for (int c = 0; c < 3; ++c) {
        if (!std::isfinite((*v)[3 * p + c])) fail("a non-finite N, V or BN vector", p);
      }
    }
  }
}

// `suffix`: the channels' (truthChannelSuffix).
SpecularScene readScene(const SweepSet& set, const SweepView& view, const SpecularSweep& sweep,
                        const std::string& suffix) {
  SpecularScene scene;
  scene.name = view.name;
  scene.cluster = view.scene;
  scene.type = view.type;
  const std::string& file = view.file;
  const ExrExpect expect{view.width, view.height, set.where};
  const std::string where = (sweep.dir / file).string();
  const std::shared_ptr<const ExrImage> shared = readVerifiedExr(set.manifest, file, where, expect);
  const ExrImage& image = *shared;
  // The roughness list must be the one these channels were traced at, not a nudged copy.
  checkAttributes(image.attributes,
                  {{"gtbake.spp", std::to_string(sweep.spp)},
                   {"gtbake.specular_roughness", specularRoughnessList(sweep.roughness)},
                   {"gtbake.specular_spp", std::to_string(sweep.specular_spp)}},
                  where, "sweep.json");
  scene.width = image.width;
  scene.height = image.height;
  const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
  const std::vector<float>& mask = need(image, "mask", where, "(not a gtbake sweep EXR)");
  scene.mask.resize(pixels);
  for (std::size_t p = 0; p < pixels; ++p) scene.mask[p] = mask[p] != 0.0f ? 1 : 0;
  scene.A = need(image, "A", where, "(not a gtbake sweep EXR)");
  const char* kVectors = "(traced by an older gtbake sweep: rerun it)";
  for (const char* prefix : {"N", "V", "BN"}) {
    std::vector<float>& out = prefix[0] == 'N'   ? scene.normal
                              : prefix[0] == 'V' ? scene.view
                                                 : scene.bent;
    out.resize(3 * pixels);
    int c = 0;
    for (const char* axis : {"X", "Y", "Z"}) {
      const std::vector<float>& ch = need(image, prefix + std::string(axis), where, kVectors);
      for (std::size_t p = 0; p < pixels; ++p) out[3 * p + c] = ch[p];
      ++c;
    }
  }
  for (double r : sweep.roughness) {
    const std::string name = specularChannelName(r) + suffix;
    if (image.channels.count(name) == 0) throw Error(where + " " + kNoSpecular);
    scene.S.push_back(need(image, name, where, kNoSpecular));
    scene.H0.push_back(need(image, "H0." + name, where, kNoSpecular));
    scene.H1.push_back(need(image, "H1." + name, where, kNoSpecular));
  }
  checkRanges(scene, where);
  return scene;
}

// The sweep's settings as specular occlusion needs them: the roughness list (checked as `gtbake
// sweep` checks its options) and the VNDF samples.
void readSettings(const SweepSet& set, SpecularSweep* sweep) {
  sweep->spp = set.settings.spp;
  if (set.settings.specular_roughness.empty()) {
    throw Error("sweep " + sweep->dir.string() + " " + kNoSpecular);
  }
  sweep->roughness = set.settings.specular_roughness;
  sweep->specular_spp = set.settings.specular_spp;
  try {
    validateSpecularOptions(sweep->roughness, sweep->specular_spp);
  } catch (const Error& e) {
    throw Error(set.where + ": settings do not describe a sweep gtbake could trace (" + e.what() +
                ")");
  }
}

}  // namespace

SpecularSweep readSpecularSweep(const fs::path& dir, std::optional<double> radius) {
  const SweepSet set = readSweepSet(dir);
  SpecularSweep sweep;
  sweep.dir = dir;
  sweep.radius = radius;
  readSettings(set, &sweep);
  const std::string suffix = truthChannelSuffix(set, radius);
  for (const SweepView& view : set.views) {
    sweep.scenes.push_back(readScene(set, view, sweep, suffix));
  }
  return sweep;
}

void useScreenEstimate(SpecularSweep* sweep, const AoInput& input) {
  const ScreenEstimateSet set(input);
  for (SpecularScene& scene : sweep->scenes) {
    ImageEstimate e = set.read(scene.name, sweep->dir, true);
    if (e.width != scene.width || e.height != scene.height || e.mask != scene.mask) {
      throw Error(e.file + ": its mask is not the one of the sweep's image '" + scene.name +
                  "' (screen-ao was run on another sweep; rerun it)");
    }
    scene.A = std::move(e.A);
    scene.bent = std::move(e.bent);
  }
}

}  // namespace gtbake
