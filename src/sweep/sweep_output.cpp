#include "sweep/sweep_output.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/output_set.h"
#include "common/sha256.h"
#include "common/text_escape.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

nlohmann::ordered_json rate(double seconds, std::uint64_t rays) {
  return seconds > 0.0 ? nlohmann::ordered_json(static_cast<double>(rays) / seconds)
                       : nlohmann::ordered_json(nullptr);
}

struct ViewImage {
  std::vector<ExrChannel> channels;
  std::uint64_t unmasked = 0;
  std::uint64_t rays = 0;
};

// Places every tile of view v into whole-image channels, checking each tile belongs there.
ViewImage assembleView(const SweepIdentity& identity, const TilePlan& plan, int s,
                       const std::function<TileData(int)>& load) {
  ViewImage image;
  const std::size_t pixels = static_cast<std::size_t>(plan.width) * plan.height;
  const std::string& name = identity.views[s];
  for (int index = 0; index < plan.tiles_of[s]; ++index) {
    const int t = plan.find(s, index);
    const Tile& planned = plan.tiles[t];
    const TileData tile = load(t);
    const std::string where = "tile " + name + ":" + std::to_string(index);
    if (tile.key != identity.key) throw Error(where + " belongs to a different sweep");
    if (tile.view != name || tile.index != index || tile.rect.x0 != planned.rect.x0 ||
        tile.rect.y0 != planned.rect.y0 || tile.rect.x1 != planned.rect.x1 ||
        tile.rect.y1 != planned.rect.y1) {
      throw Error(where + " holds other pixels than the plan's");
    }
    if (image.channels.empty()) {
      for (const ExrChannel& c : tile.channels) {
        image.channels.push_back({c.name, std::vector<float>(pixels, 0.0f)});
      }
    }
    if (tile.channels.size() != image.channels.size()) throw Error(where + " has other channels");
    for (std::size_t c = 0; c < tile.channels.size(); ++c) {
      if (tile.channels[c].name != image.channels[c].name) {
        throw Error(where + " has other channels");
      }
      const std::vector<float>& from = tile.channels[c].pixels;
      std::vector<float>& to = image.channels[c].pixels;
      for (int j = planned.rect.y0; j < planned.rect.y1; ++j) {
        const std::size_t src =
            static_cast<std::size_t>(j - planned.rect.y0) * planned.rect.width();
        std::copy(from.begin() + src, from.begin() + src + planned.rect.width(),
                  to.begin() + static_cast<std::size_t>(j) * plan.width + planned.rect.x0);
      }
    }
    for (std::uint8_t m : tile.mask) image.unmasked += m;
    image.rays += tile.rays;
  }
  return image;
}

// A view's files: its EXR (every channel) and its A and G050 previews (8-bit PNG, [0, 1]).
std::vector<std::pair<std::string, std::string>> viewFiles(
    const TilePlan& plan, const ViewImage& image,
    const std::map<std::string, std::string>& attributes, const std::string& slug) {
  std::vector<std::pair<std::string, std::string>> files;
  files.emplace_back(slug + ".exr", encodeExr(plan.width, plan.height, image.channels, attributes));
  for (const ExrChannel& c : image.channels) {
    if (c.name == "A" || c.name == "G050") {
      files.emplace_back(slug + "_" + c.name + ".png",
                         encodePng(plan.width, plan.height, 1, toGray8(c.pixels, 0.0f, 1.0f)));
    }
  }
  return files;
}

// One view assembled from its tiles and encoded: what writeSweepOutputs adds and reports.
struct EncodedView {
  std::vector<std::pair<std::string, std::string>> files;
  std::string gltf;  // the scene file, relative to the output
  double mean_a = 0.0;
  std::uint64_t unmasked = 0;
  std::uint64_t rays = 0;
  double write_seconds = 0.0;
  std::exception_ptr error;  // rethrown in view order, so the first bad view is the one named
};

EncodedView encodeView(const fs::path& out, const SweepIdentity& identity, const TilePlan& plan,
                       const std::vector<ViewRun>& runs, std::size_t s,
                       const std::function<TileData(int)>& load) {
  EncodedView v;
  try {
    const auto start = std::chrono::steady_clock::now();
    const std::string& name = identity.views[s];
    const ViewImage image = assembleView(identity, plan, static_cast<int>(s), load);
    if (image.unmasked == 0) {
      throw Error(
          "view " + name + " of " + runs[s].gltf.string() +
          ": no pixel sees geometry (every camera ray escapes); aim the camera at the scene");
    }
    v.gltf = relativePath(runs[s].gltf, out);
    std::map<std::string, std::string> attributes = identity.attributes;
    attributes["gtbake.scene"] = v.gltf;
    v.files = viewFiles(plan, image, attributes, fileSlug(name));  // docs/limits.md §Names
    double sum_a = 0.0;
    for (float a : image.channels.at(0).pixels) sum_a += a;
    v.mean_a = sum_a / static_cast<double>(image.unmasked);
    v.unmasked = image.unmasked;
    v.rays = image.rays;
    v.write_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  } catch (...) {
    v.error = std::current_exception();
  }
  return v;
}

// Views assembled and encoded at once, side by side: a batch's images held in memory together.
constexpr std::size_t kViewBatch = 8;

}  // namespace

void sealIdentity(SweepIdentity* identity) {
  nlohmann::ordered_json j;
  j["version"] = identity->version;
  j["settings"] = identity->settings;
  j["attributes"] = identity->attributes;
  j["views"] = identity->views;
  j["view_scene"] = identity->view_scene;
  j["view_type"] = identity->view_type;
  j["view_sha256"] = identity->view_sha256;
  j["view_triangles"] = identity->view_triangles;
  j["view_cameras"] = identity->view_cameras;
  j["width"] = identity->width;
  j["height"] = identity->height;
  j["camera"] = identity->camera;
  j["tile_side"] = kTileSide;
  identity->key = sha256Hex(j.dump());
}

namespace {

// Adds one encoded view (in view order) to the set, the console table, the result and
// sweep.json's views.
void addView(OutputSet* output, const SweepIdentity& identity, const TilePlan& plan,
             const std::vector<ViewRun>& runs, std::size_t s, EncodedView v, SweepResult* result,
             nlohmann::ordered_json* entries) {
  if (v.error) std::rethrow_exception(v.error);
  const std::string& name = identity.views[s];
  const fs::path exr = output->dir() / v.files.front().first;
  for (auto& [file, bytes] : v.files) output->add(file, bytes);
  const double trace_seconds = runs[s].trace_seconds;
  const double seconds = runs[s].build_seconds + trace_seconds + v.write_seconds;
  std::printf("%-16s %9llu %8.4f %9.2f %9.2f\n", name.c_str(),
              static_cast<unsigned long long>(v.unmasked), v.mean_a, seconds,
              trace_seconds > 0.0 ? 1e-6 * static_cast<double>(v.rays) / trace_seconds : 0.0);
  std::fflush(stdout);
  result->views.push_back({exr, seconds, v.rays});
  result->seconds += runs[s].build_seconds + trace_seconds;  // the writes: their wall, below
  result->rays += v.rays;
  nlohmann::ordered_json entry;
  entry["name"] = name;
  entry["scene"] = identity.view_scene[s];
  entry["type"] = identity.view_type[s];
  entry["file"] = exr.filename().string();
  entry["gltf"] = v.gltf;
  entry["width"] = plan.width;
  entry["height"] = plan.height;
  entry["triangles"] = identity.view_triangles[s];
  entry["camera"] = identity.view_cameras[s];
  entry["unmasked_pixels"] = v.unmasked;
  entry["mean_A"] = v.mean_a;
  entry["seconds"] = seconds;
  entry["build_seconds"] = runs[s].build_seconds;
  entry["trace_seconds"] = trace_seconds;
  entry["rays"] = v.rays;
  entry["rays_per_second"] = rate(trace_seconds, v.rays);
  entries->push_back(std::move(entry));
}

}  // namespace

SweepResult writeSweepOutputs(const fs::path& out, const SweepIdentity& identity,
                              const TilePlan& plan, const std::vector<ViewRun>& runs, int threads,
                              const std::function<TileData(int)>& load) {
  OutputSet output(out, "sweep");  // committed whole at the end (output_set.h)
  SweepResult result;
  nlohmann::ordered_json view_entries = nlohmann::ordered_json::array();
  std::printf("%-16s %9s %8s %9s %9s\n", "view", "pixels", "mean A", "seconds", "Mrays/s");
  const auto writing = std::chrono::steady_clock::now();
  for (std::size_t first = 0; first < identity.views.size(); first += kViewBatch) {
    const std::size_t count = std::min(kViewBatch, identity.views.size() - first);
    std::vector<EncodedView> batch(count);
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t k) {
      batch[k] = encodeView(out, identity, plan, runs, first + k, load);
    });
    for (std::size_t k = 0; k < count; ++k) {
      addView(&output, identity, plan, runs, first + k, std::move(batch[k]), &result,
              &view_entries);
    }
  }
  // Views are written side by side, so each view's seconds hold its own write and the total the
  // writing's wall time: the whole sweep's wall time (views are traced one after another).
  result.seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - writing).count();
  std::printf(
      "%-16s %9s %8s %9.2f %9.2f\n", "total", "", "", result.seconds,
      result.seconds > 0.0 ? 1e-6 * static_cast<double>(result.rays) / result.seconds : 0.0);

  nlohmann::ordered_json json;
  json["gtbake_version"] = identity.version;
  json["settings"] = identity.settings;
  json["settings"]["threads"] = threads;
  json["views"] = std::move(view_entries);
  json["totals"] = {{"seconds", result.seconds},
                    {"rays", result.rays},
                    {"rays_per_second", rate(result.seconds, result.rays)}};
  output.setSettings(json["settings"]);
  output.add("sweep.json", json.dump(2) + "\n");
  output.commit();
  return result;
}

}  // namespace gtbake
