// `gtbake sweep` (SPEC §2): validate, load every scene, trace each one's escape image, write the
// EXR, PNG previews and sweep.json, print the summary table.
#include "sweep/sweep_command.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/threads.h"
#include "gtbake_version.h"
#include "scene/scene.h"
#include "sweep/escape_image.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

constexpr int kMaxSpp = 1 << 20;      // keeps counts in uint32 and a pixel's walks < 1 s
constexpr int kMaxResolution = 8192;  // pixels per side; 8192² × 2(K+1) counts fits in memory
constexpr int kMaxBounces = 16;       // ρ^17 ≤ 0.9^17 ≈ 0.17 of p_17: beyond that nobody asks

bool isGltf(const fs::path& path) {
  const std::string ext = path.extension().string();
  return ext == ".gltf" || ext == ".glb";
}

void validateOptions(const SweepOptions& o) {
  if (o.spp < 2 || o.spp > kMaxSpp || o.spp % 2 != 0) {
    throw Error("--spp must be an even number in [2, " + std::to_string(kMaxSpp) + "], got " +
                std::to_string(o.spp));
  }
  if (o.width < 1 || o.width > kMaxResolution || o.height < 1 || o.height > kMaxResolution) {
    throw Error("--res must be WxH with each side in [1, " + std::to_string(kMaxResolution) +
                "], got " + std::to_string(o.width) + "x" + std::to_string(o.height));
  }
  if (o.bounces < 0 || o.bounces > kMaxBounces) {
    throw Error("--bounces must be in [0, " + std::to_string(kMaxBounces) + "], got " +
                std::to_string(o.bounces));
  }
  if (!(o.radius > 0.0)) throw Error("--radius must be a positive distance in metres");
  validateSpecularOptions(o.specular_roughness, o.specular_spp);
  if (o.threads < 0) throw Error("--threads must be 0 (all cores) or a positive count");
  if (o.scenes.empty()) throw Error("no scenes given: pass --scenes DIR|FILE...");
  if (o.out.empty()) throw Error("no output directory given: pass --out DIR");
}

// Each input is a .gltf/.glb file, or a directory whose *.gltf files are all taken, sorted.
std::vector<fs::path> resolveSceneFiles(const std::vector<fs::path>& inputs) {
  std::vector<fs::path> files;
  for (const fs::path& input : inputs) {
    std::error_code ec;
    if (fs::is_directory(input, ec)) {
      std::vector<fs::path> found;
      for (const auto& entry : fs::directory_iterator(input, ec)) {
        if (entry.is_regular_file() && entry.path().extension() == ".gltf") {
          found.push_back(entry.path());
        }
      }
      if (ec) throw Error("cannot list scene directory " + input.string() + ": " + ec.message());
      if (found.empty()) throw Error("scene directory " + input.string() + " has no .gltf files");
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(input, ec)) {
      if (!isGltf(input)) throw Error("scene " + input.string() + " is not a .gltf or .glb file");
      files.push_back(input);
    } else {
      throw Error("no such scene file or directory: " + input.string());
    }
  }
  std::set<std::string> names;
  for (const fs::path& f : files) {
    if (!names.insert(f.stem().string()).second) {
      throw Error("two scenes are named '" + f.stem().string() + "' (" + f.string() +
                  "); outputs are named by file stem");
    }
  }
  return files;
}

void ensureWritableDirectory(const fs::path& out) {
  ensureDirectory(out);
  if (::access(out.c_str(), W_OK) != 0)
    throw Error("output directory " + out.string() + " is not writable");
}

std::string formatNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", value);
  return text;
}

nlohmann::ordered_json rate(double seconds, std::uint64_t rays) {
  return seconds > 0.0 ? nlohmann::ordered_json(static_cast<double>(rays) / seconds)
                       : nlohmann::ordered_json(nullptr);
}

}  // namespace

SweepResult runSweep(const SweepOptions& options) {
  validateOptions(options);
  const std::vector<fs::path> files = resolveSceneFiles(options.scenes);
  // Load every scene before writing anything: a bad scene fails the run with no output.
  std::vector<Scene> scenes;
  for (const fs::path& file : files) {
    scenes.push_back(readGltfScene(file));
    scenes.back().name = file.stem().string();
    if (scenes.back().triangles.empty())
      throw Error("scene " + file.string() + " has no triangles");
  }
  ensureWritableDirectory(options.out);
  const ThreadLimit threads(options.threads);

  WalkSettings settings;
  settings.spp = options.spp;
  settings.bounces = options.bounces;
  settings.radius = std::isinf(options.radius) ? INFINITY : static_cast<float>(options.radius);
  settings.seed = options.seed;
  settings.stratify_first_bounce = options.stratify_first_bounce;
  settings.specular_roughness = options.specular_roughness;
  settings.specular_spp = options.specular_roughness.empty() ? 0 : options.specular_spp;

  SweepResult result;
  nlohmann::ordered_json scene_entries = nlohmann::ordered_json::array();
  std::printf("%-16s %9s %8s %9s %9s\n", "scene", "pixels", "mean A", "seconds", "Mrays/s");
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    const Scene& scene = scenes[s];
    const auto start = std::chrono::steady_clock::now();
    const EmbreeTracer tracer(scene);
    settings.scene_key = sceneStreamKey(scene.name);
    const EscapeImage image = traceEscapeImage(tracer, scene.camera, options.width, options.height,
                                               settings, "sweep " + scene.name, options.progress);
    const std::vector<ExrChannel> channels = escapeChannels(image);
    const std::string gltf = relativePath(files[s], options.out);
    const std::map<std::string, std::string> attributes = {
        {"gtbake.version", GTBAKE_VERSION},
        {"gtbake.spp", std::to_string(options.spp)},
        {"gtbake.bounces", std::to_string(options.bounces)},
        {"gtbake.seed", std::to_string(options.seed)},
        {"gtbake.radius", std::isinf(options.radius) ? "inf" : formatNumber(options.radius)},
        {"gtbake.scene", gltf},
        {"gtbake.stratified_first_bounce", options.stratify_first_bounce ? "1" : "0"},
        {"gtbake.specular_roughness", specularRoughnessList(options.specular_roughness)},
        {"gtbake.specular_spp", std::to_string(settings.specular_spp)}};
    const fs::path exr = options.out / (scene.name + ".exr");
    writeExr(exr, options.width, options.height, channels, attributes);
    for (const ExrChannel& c : channels) {
      if (c.name == "A" || c.name == "G050") {
        writePng(options.out / (scene.name + "_" + c.name + ".png"), options.width, options.height,
                 1, toGray8(c.pixels, 0.0f, 1.0f));
      }
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const std::uint64_t unmasked = image.unmaskedPixels();
    double sum_a = 0.0;
    for (std::size_t p = 0; p < channels[0].pixels.size(); ++p) sum_a += channels[0].pixels[p];
    const double mean_a = unmasked > 0 ? sum_a / static_cast<double>(unmasked) : 0.0;
    std::printf("%-16s %9llu %8.4f %9.2f %9.2f\n", scene.name.c_str(),
                static_cast<unsigned long long>(unmasked), mean_a, seconds,
                image.seconds > 0.0 ? 1e-6 * static_cast<double>(image.rays) / image.seconds : 0.0);
    std::fflush(stdout);

    result.scenes.push_back({exr, seconds, image.rays});
    result.seconds += seconds;
    result.rays += image.rays;
    nlohmann::ordered_json entry;
    entry["name"] = scene.name;
    entry["file"] = exr.filename().string();
    entry["gltf"] = gltf;
    entry["width"] = options.width;
    entry["height"] = options.height;
    entry["unmasked_pixels"] = unmasked;
    entry["mean_A"] = mean_a;
    entry["seconds"] = seconds;
    entry["build_seconds"] = tracer.buildSeconds();
    entry["trace_seconds"] = image.seconds;
    entry["rays"] = image.rays;
    entry["rays_per_second"] = rate(image.seconds, image.rays);
    scene_entries.push_back(std::move(entry));
  }
  std::printf(
      "%-16s %9s %8s %9.2f %9.2f\n", "total", "", "", result.seconds,
      result.seconds > 0.0 ? 1e-6 * static_cast<double>(result.rays) / result.seconds : 0.0);

  nlohmann::ordered_json json;
  json["gtbake_version"] = GTBAKE_VERSION;
  nlohmann::ordered_json& settings_json = json["settings"];
  settings_json["spp"] = options.spp;
  settings_json["width"] = options.width;
  settings_json["height"] = options.height;
  settings_json["bounces"] = options.bounces;
  settings_json["radius"] = std::isinf(options.radius) ? nlohmann::ordered_json(nullptr)
                                                       : nlohmann::ordered_json(options.radius);
  settings_json["seed"] = options.seed;
  settings_json["threads"] = threads.threads();
  settings_json["albedos"] = kSweepAlbedos;
  settings_json["stratified_first_bounce"] = options.stratify_first_bounce;
  settings_json["specular_roughness"] = options.specular_roughness;
  settings_json["specular_spp"] = settings.specular_spp;
  json["scenes"] = std::move(scene_entries);
  json["totals"] = {{"seconds", result.seconds},
                    {"rays", result.rays},
                    {"rays_per_second", rate(result.seconds, result.rays)}};
  writeFileAtomically(options.out / "sweep.json", json.dump(2) + "\n");
  return result;
}

}  // namespace gtbake
