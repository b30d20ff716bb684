#include "fit/sweep_data.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>

#include "common/error.h"
#include "common/image_io.h"
#include "common/output_set.h"
#include "common/provenance.h"
#include "sweep/sweep_set.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

// A stored G### channel may differ from Σ ρ^k P_k recomputed from the stored P_k by float
// rounding only (unitless; K+1 float32 roundings of values ≤ 1 stay below 1e-6, so 1e-4 flags a
// wrong albedo without flagging rounding).
constexpr double kAlbedoConsistencyTolerance = 1e-4;

// G(ρ) = Σ_{k=0..K} ρ^k P_k with P_0 = A (docs/sweep.md §1), evaluated by Horner's rule in double.
double multiBounceG(const std::vector<const std::vector<float>*>& p, std::size_t pixel,
                    double rho) {
  double g = 0.0;
  for (std::size_t k = p.size(); k-- > 0;) g = g * rho + static_cast<double>((*p[k])[pixel]);
  return g;
}

}  // namespace

std::string albedoChannel(double rho) {
  char name[16];
  std::snprintf(name, sizeof(name), "G%03d", static_cast<int>(std::lround(rho * 100.0)));
  return name;
}

namespace {

// What the fit needs of the sweep's settings: at least two albedos to fit across.
void requireFitSettings(const SweepSet& set) {
  if (set.settings.albedos.size() < 2) {
    throw Error(set.where + ": settings 'albedos' must list at least two albedos");
  }
}

// The channels of one scene's EXR: p[s][k] for s = full, H0, H1 (k = 0 is A), g[j] = G(ρ_j).
struct SceneChannels {
  std::vector<const std::vector<float>*> p[3];
  std::vector<const std::vector<float>*> g;
  std::vector<std::string> g_names;
  const std::vector<float>* mask = nullptr;
};

// Looks every channel up (a missing one is an error naming it) and rejects G### channels whose
// albedo sweep.json does not list.
SceneChannels requireChannels(const ExrImage& image, const std::string& file,
                              const SweepSettings& sj, const std::string& suffix) {
  SceneChannels c;
  c.mask = &image.channel("mask", file);
  const std::string prefix[3] = {"", "H0.", "H1."};
  for (int s = 0; s < 3; ++s) {
    c.p[s].push_back(&image.channel(prefix[s] + "A" + suffix, file));
    for (int k = 1; k <= sj.bounces; ++k) {
      c.p[s].push_back(&image.channel(prefix[s] + "P" + std::to_string(k) + suffix, file));
    }
  }
  for (double rho : sj.albedos) {
    const std::string name = albedoChannel(rho) + suffix;
    if (image.channels.count(name) == 0) {
      throw Error(file + ": albedo " + std::to_string(rho) + " listed in sweep.json has no " +
                  name + " channel");
    }
    c.g.push_back(&image.channel(name, file));
    c.g_names.push_back(name);
  }
  for (const auto& named_channel : image.channels) {
    const std::string& name = named_channel.first;
    const bool g_channel = name.size() == 4 && name[0] == 'G' &&
                           name.find_first_not_of("0123456789", 1) == std::string::npos;
    bool listed = false;
    for (double rho : sj.albedos) listed = listed || albedoChannel(rho) == name;
    if (g_channel && !listed) {
      throw Error(file + ": channel " + name + " has no matching albedo in sweep.json");
    }
  }
  return c;
}

// One scene's unmasked points, every value checked (finite, G### consistent with the P_k).
struct ScenePoints {
  std::string name;
  std::string cluster;
  std::string type;
  PointSet full;
  PointSet half[2];
};

// The escape probabilities of an unmasked pixel, for the full estimate and both halves: each a
// finite fraction of walks, A = p_0 and p_k in [0, 1], their sum at most 1 (docs/sweep.md §1;
// docs/limits.md §Values). kProbabilitySumTolerance allows the float rounding of the sum.
constexpr double kProbabilitySumTolerance = 1e-5;

void checkProbabilities(const SceneChannels& c, std::size_t i, int width, const std::string& file) {
  const auto fail = [&](const char* what) {
    throw Error(file + ": " + what + " in an unmasked pixel (" + std::to_string(i % width) + ", " +
                std::to_string(i / width) + ")");
  };
  for (int s = 0; s < 3; ++s) {
    double sum = 0.0;
    for (const auto* channel : c.p[s]) {
      const float p = (*channel)[i];
      if (!std::isfinite(p)) fail("non-finite value");
      if (!(p >= 0.0f && p <= 1.0f)) fail("A or p_k outside [0, 1]");
      sum += p;
    }
    if (sum > 1.0 + kProbabilitySumTolerance) fail("A + sum of p_k above 1");
  }
}

void appendUnmaskedPoints(const SceneChannels& c, const ExrImage& image, const std::string& file,
                          const std::vector<double>& albedos, ScenePoints& out) {
  const std::size_t M = albedos.size();
  for (PointSet* set : {&out.full, &out.half[0], &out.half[1]}) set->G.resize(M);
  const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
  for (std::size_t i = 0; i < pixels; ++i) {
    if (!((*c.mask)[i] > 0.5f)) continue;
    checkProbabilities(c, i, image.width, file);
    out.full.A.push_back((*c.p[0][0])[i]);
    for (int s = 0; s < 2; ++s) out.half[s].A.push_back((*c.p[s + 1][0])[i]);
    for (std::size_t j = 0; j < M; ++j) {
      const double stored = (*c.g[j])[i];
      const double recomputed = multiBounceG(c.p[0], i, albedos[j]);
      if (!std::isfinite(stored) || std::abs(stored - recomputed) > kAlbedoConsistencyTolerance) {
        throw Error(file + ": channel " + c.g_names[j] + " is inconsistent with albedo " +
                    std::to_string(albedos[j]) + " and the P_k channels");
      }
      out.full.G[j].push_back(stored);
      for (int s = 0; s < 2; ++s)
        out.half[s].G[j].push_back(multiBounceG(c.p[s + 1], i, albedos[j]));
    }
  }
}

ScenePoints loadScene(const SweepSet& set, const SweepView& view, const std::string& suffix) {
  ScenePoints out;
  out.name = view.name;
  out.cluster = view.scene;
  out.type = view.type;
  const fs::path exr_path = set.dir / view.file;
  if (!fs::is_regular_file(exr_path)) {
    throw Error("scene '" + out.name + "' is listed in " + set.where + " but " + exr_path.string() +
                " is missing");
  }
  const std::string file = exr_path.string();
  const ExrExpect expect{view.width, view.height, "sweep.json"};
  const std::shared_ptr<const ExrImage> shared =
      readVerifiedExr(set.manifest, view.file, file, expect);
  const ExrImage& image = *shared;
  const SweepSettings& sj = set.settings;
  std::map<std::string, std::string> provenance = {{"gtbake.spp", std::to_string(sj.spp)},
                                                   {"gtbake.bounces", std::to_string(sj.bounces)}};
  if (sj.seed) provenance["gtbake.seed"] = std::to_string(*sj.seed);
  if (!view.gltf.empty()) provenance["gtbake.scene"] = view.gltf;
  checkAttributes(image.attributes, provenance, file, "sweep.json");
  appendUnmaskedPoints(requireChannels(image, file, sj, suffix), image, file, sj.albedos, out);
  const std::size_t count = out.full.A.size();
  if (view.unmasked_pixels && *view.unmasked_pixels != static_cast<std::int64_t>(count)) {
    throw Error(file + ": mask has " + std::to_string(count) +
                " unmasked pixels but sweep.json says " + std::to_string(*view.unmasked_pixels));
  }
  if (count < kMinScenePoints) {
    throw Error("scene '" + out.name + "' has " + std::to_string(count) +
                " unmasked pixels; at least " + std::to_string(kMinScenePoints) + " needed");
  }
  return out;
}

void appendPoints(const PointSet& from, PointSet& to) {
  to.A.insert(to.A.end(), from.A.begin(), from.A.end());
  to.G.resize(from.G.size());
  for (std::size_t j = 0; j < from.G.size(); ++j) {
    to.G[j].insert(to.G[j].end(), from.G[j].begin(), from.G[j].end());
  }
}

}  // namespace

SweepData loadSweep(const fs::path& dir, std::optional<double> radius, const LoadedSweeps* loaded) {
  if (loaded != nullptr) {
    const auto it = loaded->find(radius);
    if (it != loaded->end()) return it->second;
  }
  return loadSweep(dir, radius);
}

SweepData loadSweep(const fs::path& dir, std::optional<double> radius) {
  const SweepSet sj = readSweepSet(dir);
  requireFitSettings(sj);
  const std::string suffix = truthChannelSuffix(sj, radius);
  // Scenes load in parallel; the first failure in scene order is reported, so the error does not
  // depend on the thread count.
  const std::size_t S = sj.views.size();
  std::vector<ScenePoints> scenes(S);
  std::vector<std::exception_ptr> errors(S);
  tbb::parallel_for(std::size_t{0}, S, [&](std::size_t s) {
    try {
      scenes[s] = loadScene(sj, sj.views[s], suffix);
    } catch (...) {
      errors[s] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  SweepData data;
  data.dir = dir;
  data.spp = sj.settings.spp;
  data.bounces = sj.settings.bounces;
  data.albedos = sj.settings.albedos;
  for (const ScenePoints& scene : scenes) {
    const std::size_t begin = data.full.A.size();
    appendPoints(scene.full, data.full);
    for (int h = 0; h < 2; ++h) appendPoints(scene.half[h], data.half[h]);
    data.scenes.push_back({scene.name, begin, data.full.A.size(), scene.cluster, scene.type});
  }
  if (data.points() < kMinFitPoints) {
    throw Error(dir.string() + ": only " + std::to_string(data.points()) +
                " unmasked points; the fit needs at least " + std::to_string(kMinFitPoints));
  }
  return data;
}

}  // namespace gtbake
