// `gtbake sweep` (docs/index.md "Pipeline") in named steps: validate, load every scene, describe
// the sweep (its identity key), plan the tiles, trace the tiles not yet checkpointed, then write
// either the sweep's outputs (EXR, PNG previews, sweep.json, summary table) or, for a shard, its
// manifest.
#include "sweep/sweep_command.h"

#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/input_limits.h"
#include "common/output_lock.h"
#include "common/progress.h"
#include "common/text_escape.h"
#include "common/text_format.h"
#include "common/threads.h"
#include "gtbake_version.h"
#include "scene/auto_camera.h"
#include "scene/gltf_reader.h"
#include "scene/scene.h"
#include "sweep/camera_json.h"
#include "sweep/escape_image.h"
#include "sweep/shard_manifest.h"
#include "sweep/sweep_output.h"
#include "sweep/tile_plan.h"
#include "sweep/tile_store.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

constexpr int kMaxSpp = kMaxSweepSpp;  // common/input_limits.h
constexpr int kMaxBounces = kMaxSweepBounces;

bool isGltf(const fs::path& path) {
  const std::string ext = path.extension().string();
  return ext == ".gltf" || ext == ".glb";
}

void validateOptions(const SweepOptions& o) {
  if (o.spp < 2 || o.spp > kMaxSpp || o.spp % 2 != 0) {
    throw Error("--spp must be an even number in [2, " + std::to_string(kMaxSpp) + "], got " +
                std::to_string(o.spp));
  }
  if (o.width < 1 || o.width > kMaxSweepResolution || o.height < 1 ||
      o.height > kMaxSweepResolution) {
    throw Error("--res must be WxH with each side in [1, " + std::to_string(kMaxSweepResolution) +
                "], got " + std::to_string(o.width) + "x" + std::to_string(o.height));
  }
  if (o.bounces == 0) {
    throw Error(
        "--bounces 0 gives a sweep that fit and validate cannot use (they need P1); use 1 to " +
        std::to_string(kMaxBounces));
  }
  if (o.bounces < 1 || o.bounces > kMaxBounces) {
    throw Error("--bounces must be in [1, " + std::to_string(kMaxBounces) + "], got " +
                std::to_string(o.bounces));
  }
  if (!(o.radius > 0.0)) throw Error("--radius must be a positive distance in metres");
  validateSpecularOptions(o.specular_roughness, o.specular_spp);
  for (std::size_t r = 0; r < o.gbuffer_radii.size(); ++r) {
    if (!(o.gbuffer_radii[r] > 0.0) || !std::isfinite(o.gbuffer_radii[r]) ||
        (r > 0 && (!(o.gbuffer_radii[r] > o.gbuffer_radii[r - 1]) ||
                   gbufferRadiusChannelName(o.gbuffer_radii[r]) ==
                       gbufferRadiusChannelName(o.gbuffer_radii[r - 1])))) {
      throw Error(
          "--gbuffer-radius must be ascending positive finite metres with distinct channel names "
          "(%g), got " +
          gbufferRadiusList(o.gbuffer_radii));
    }
  }
  if (o.shards < 0 || o.shards > kMaxShards ||
      (o.shards > 0 && (o.shard < 0 || o.shard >= o.shards))) {
    throw Error("--shard must be I/N with 0 <= I < N <= " + std::to_string(kMaxShards) + ", got " +
                std::to_string(o.shard) + "/" + std::to_string(o.shards));
  }
  if (o.scenes.empty()) throw Error("no scenes given: pass --scenes DIR|FILE...");
  if (o.out.empty()) throw Error("no output directory given: pass --out DIR");
}

// Each input is a .gltf/.glb file, or a directory whose .gltf and .glb files are all taken, sorted.
std::vector<fs::path> resolveSceneFiles(const std::vector<fs::path>& inputs) {
  std::vector<fs::path> files;
  for (const fs::path& input : inputs) {
    std::error_code ec;
    if (fs::is_directory(input, ec)) {
      std::vector<fs::path> found;
      for (const auto& entry : fs::directory_iterator(input, ec)) {
        if (entry.is_regular_file() && isGltf(entry.path())) {
          found.push_back(entry.path());
        }
      }
      if (ec) throw Error("cannot list scene directory " + input.string() + ": " + ec.message());
      if (found.empty())
        throw Error("scene directory " + input.string() + " has no .gltf files (nor .glb)");
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
    requireUtf8(f.string(), "a scene path");  // sweep.json records it (docs/limits.md §Paths)
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

// One image of the sweep: a scene seen from one camera.
struct SweepView {
  std::size_t scene = 0;  // index into SweepInputs::scenes and ::files
  PerspectiveCamera camera;
  std::string name;  // the glTF stem, or <stem>_v<k> for automatic views
};

struct SweepInputs {
  std::vector<fs::path> files;
  std::vector<Scene> scenes;        // per file; name = the stem, type as read ("" = none)
  std::vector<std::string> sha256;  // per file: GltfReadInfo::input_sha256
  std::vector<SweepView> views;
};

// A file whose cameras are all orthographic gets automatic views: say which were ignored, why.
void noteIgnoredCameras(const fs::path& file, const std::vector<std::string>& orthographic) {
  if (orthographic.empty()) return;
  std::string names;
  for (std::string name : orthographic) {
    for (char& c : name) c = (c >= 0 && c < 0x20) || c == 0x7f ? '?' : c;  // one line on stderr
    names += (names.empty() ? "'" : ", '") + name + "'";
  }
  std::fprintf(stderr,
               "sweep: %s: ignoring orthographic camera%s %s (gtbake traces perspective views "
               "only); using %d automatic views (--camera auto:K)\n",
               file.string().c_str(), orthographic.size() > 1 ? "s" : "", names.c_str(),
               kAutoViews);
}

// Loads every scene before anything is written: a bad scene fails the run with no output. A
// file gets its own camera, or kAutoViews automatic views when it has none; --camera auto[:K]
// gives every file K automatic views (auto_camera.h).
SweepInputs loadScenes(const std::vector<fs::path>& files, const SweepOptions& o) {
  const int auto_views = parseAutoCamera(o.camera);
  SweepInputs in;
  in.files = files;
  std::set<std::string> names;
  for (const fs::path& file : files) {
    GltfReadInfo info;
    GltfReadOptions read;
    read.camera = auto_views > 0 ? "" : o.camera;
    read.allow_no_camera = true;
    in.scenes.push_back(readGltfScene(file, read, &info));
    in.sha256.push_back(info.input_sha256);
    Scene& scene = in.scenes.back();
    scene.name = file.stem().string();
    if (scene.triangles.empty()) throw Error("scene " + file.string() + " has no triangles");
    if (auto_views == 0 && info.perspective_cameras > 1) {
      std::fprintf(stderr, "sweep: %s: camera %d '%s' of %d (choose with --camera NAME|INDEX)\n",
                   file.string().c_str(), info.camera_instance, info.camera_name.c_str(),
                   info.perspective_cameras);
    }
    const int k_views = auto_views > 0                  ? auto_views
                        : info.perspective_cameras == 0 ? kAutoViews
                                                        : 0;
    if (auto_views == 0 && k_views > 0) noteIgnoredCameras(file, info.orthographic_cameras);
    std::vector<SweepView> views;
    if (k_views == 0) views.push_back({in.scenes.size() - 1, scene.camera, scene.name});
    const auto cameras = autoCameras(scene, k_views, static_cast<double>(o.width) / o.height);
    for (int k = 0; k < k_views; ++k) {
      views.push_back({in.scenes.size() - 1, cameras[k], scene.name + "_v" + std::to_string(k)});
    }
    for (const SweepView& v : views) {
      if (!names.insert(v.name).second) {
        throw Error("two views are named '" + v.name + "' (" + file.string() +
                    "); outputs are named by file stem and view");
      }
      in.views.push_back(v);
    }
  }
  return in;
}

WalkSettings walkSettings(const SweepOptions& o) {
  WalkSettings settings;
  settings.spp = o.spp;
  settings.bounces = o.bounces;
  settings.radius = std::isinf(o.radius) ? INFINITY : static_cast<float>(o.radius);
  settings.seed = o.seed;
  settings.stratify_first_bounce = o.stratify_first_bounce;
  settings.specular_roughness = o.specular_roughness;
  settings.specular_spp = o.specular_roughness.empty() ? 0 : o.specular_spp;
  for (double r : o.gbuffer_radii) settings.gbuffer_radii.push_back(static_cast<float>(r));
  settings.transfer = o.transfer;
  return settings;
}

// A whole view, assembled from its tiles, and its encoded EXR (sweep_output.cpp, one view at a
// time): about 2 x channels x pixels floats, checked before any work (docs/limits.md "Bounded
// work and memory"). Shards hold tiles only; merge assembles the views.
void checkImageMemory(const SweepOptions& o) {
  if (o.shards > 0) return;
  const std::size_t channels = escapeChannels(makeEscapeImage(1, 1, walkSettings(o))).size();
  const std::uint64_t pixels = static_cast<std::uint64_t>(o.width) * o.height;
  checkMemoryEstimate(2 * channels * pixels * sizeof(float),
                      "sweep --res " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                          " (" + std::to_string(channels) +
                          " channels of a view from --bounces, --specular-roughness and "
                          "--gbuffer-radius; a smaller --res needs less)");
}

// Everything that determines a pixel's values (the thread count and shard do not), as recorded in
// sweep.json's "settings" (plus "threads") and the EXR attributes (plus "gtbake.scene").
SweepIdentity describeSweep(const SweepOptions& o, const SweepInputs& in) {
  SweepIdentity id;
  id.version = GTBAKE_VERSION;
  nlohmann::ordered_json& settings = id.settings;
  settings["spp"] = o.spp;
  settings["width"] = o.width;
  settings["height"] = o.height;
  settings["bounces"] = o.bounces;
  settings["radius"] =
      std::isinf(o.radius) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(o.radius);
  settings["seed"] = o.seed;
  settings["albedos"] = kSweepAlbedos;
  settings["stratified_first_bounce"] = o.stratify_first_bounce;
  settings["specular_roughness"] = o.specular_roughness;
  settings["specular_spp"] = o.specular_roughness.empty() ? 0 : o.specular_spp;
  settings["gbuffer_radii"] = o.gbuffer_radii;
  settings["transfer"] = o.transfer;
  id.attributes = {
      {"gtbake.version", GTBAKE_VERSION},
      {"gtbake.spp", std::to_string(o.spp)},
      {"gtbake.bounces", std::to_string(o.bounces)},
      {"gtbake.seed", std::to_string(o.seed)},
      {"gtbake.radius", std::isinf(o.radius) ? "inf" : formatNumber(o.radius, "%.9g")},
      {"gtbake.stratified_first_bounce", o.stratify_first_bounce ? "1" : "0"},
      {"gtbake.specular_roughness", specularRoughnessList(o.specular_roughness)},
      {"gtbake.specular_spp", std::to_string(o.specular_roughness.empty() ? 0 : o.specular_spp)},
      {"gtbake.gbuffer_radii", gbufferRadiusList(o.gbuffer_radii)},
      {"gtbake.transfer", o.transfer ? "1" : "0"}};
  for (const SweepView& v : in.views) {
    const Scene& scene = in.scenes[v.scene];
    id.views.push_back(v.name);
    id.view_scene.push_back(scene.name);
    id.view_type.push_back(scene.type.empty() ? scene.name : scene.type);
    id.view_sha256.push_back(in.sha256[v.scene]);
    id.view_triangles.push_back(scene.triangles.size());
    id.view_cameras.push_back(cameraJson(v.camera));
  }
  id.width = o.width;
  id.height = o.height;
  id.camera = o.camera;
  sealIdentity(&id);
  return id;
}

std::string signalName(int signal) {
  return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : std::to_string(signal);
}

// While alive, SIGINT and SIGTERM only raise a flag: the tiles in flight finish and are saved, no
// new tile starts. The first such signal puts the previous handler back, so a second one stops
// at once (removing this process's temporary files, atomic_file.h).
std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs a lock-free flag");
struct sigaction g_previous_int;  // the handlers before StopOnSignals (atomic_file.h's cleanup)
struct sigaction g_previous_term;

extern "C" void onStopSignal(int signal) {
  g_stop_signal.store(signal);
  // sigaction is async-signal-safe: the next such signal goes to the previous handler.
  sigaction(signal, signal == SIGINT ? &g_previous_int : &g_previous_term, nullptr);
}

class StopOnSignals {
 public:
  StopOnSignals() {
    g_stop_signal.store(0);
    struct sigaction action;
    std::memset(&action, 0, sizeof(action));
    action.sa_handler = onStopSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = 0;
    sigaction(SIGINT, &action, &g_previous_int);
    sigaction(SIGTERM, &action, &g_previous_term);
  }
  ~StopOnSignals() {
    sigaction(SIGINT, &g_previous_int, nullptr);
    sigaction(SIGTERM, &g_previous_term, nullptr);
  }
  StopOnSignals(const StopOnSignals&) = delete;
  StopOnSignals& operator=(const StopOnSignals&) = delete;
  int signal() const { return g_stop_signal.load(); }
};

// <out>/sweep-tiles, holding this sweep's checkpointed tiles. The directory's "key" file names
// the sweep; tiles of another sweep are removed (or, with --resume, refused).
fs::path openTileDirectory(const SweepOptions& o, const SweepIdentity& id) {
  const fs::path dir = o.out / kTileDirectory;
  const fs::path key_file = dir / "key";
  std::error_code ec;
  if (!fs::exists(dir, ec)) {
    if (o.resume) {
      throw Error("nothing to resume: " + dir.string() +
                  " does not exist (the sweep finished, or never started there)");
    }
  } else if (!fs::is_regular_file(key_file, ec) || readFile(key_file) != id.key + "\n") {
    if (o.resume) {
      throw Error("cannot resume: " + dir.string() +
                  " holds tiles of another sweep (other settings, seed, scenes or gtbake version); "
                  "run without --resume to start over");
    }
    std::fprintf(stderr, "sweep: removing the tiles of another sweep in %s\n", dir.c_str());
    removeShardManifest(o.out);  // first: a shard set never lists tiles that are gone
    fs::remove_all(dir, ec);
    if (ec) throw Error("cannot remove " + dir.string() + ": " + ec.message());
  }
  ensureDirectory(dir);
  if (!fs::exists(key_file, ec)) writeFileAtomically(key_file, id.key + "\n");
  cleanStaleTemporaries(dir);  // a killed run leaves the tiles it was writing half-written
  return dir;
}

// A checkpointed tile that is whole and belongs to this sweep and place; corrupt ones are
// reported and traced again.
bool haveTile(const fs::path& path, const SweepIdentity& id, const Tile& tile) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  try {
    const TileData t = readTile(path);
    return t.key == id.key && t.view == id.views[tile.view] && t.index == tile.index &&
           t.rect.x0 == tile.rect.x0 && t.rect.y0 == tile.rect.y0 && t.rect.x1 == tile.rect.x1 &&
           t.rect.y1 == tile.rect.y1;
  } catch (const Error& e) {
    std::fprintf(stderr, "sweep: tracing again: %s\n", e.what());
    return false;
  }
}

struct TraceReport {
  std::vector<ViewRun> runs;  // per view: glTF, build and trace time of this run
  std::size_t traced = 0;     // tiles traced by this run
  std::size_t reused = 0;     // tiles found checkpointed
  std::uint64_t rays = 0;     // traced by this run
  int signal = 0;             // the stop signal, or 0 if every tile is done
};

// Traces the tiles `mine` that are not checkpointed yet, view by view (TBB over the tiles, and
// inside each tile over 8×8 blocks), saving each tile as it finishes. Stops starting tiles after
// SIGINT/SIGTERM.
TraceReport traceTiles(const SweepOptions& o, const SweepInputs& in, const SweepIdentity& id,
                       const TilePlan& plan, const std::vector<int>& mine, const fs::path& dir) {
  TraceReport report;
  WalkSettings settings = walkSettings(o);
  const std::string prefix =
      o.shards > 0 ? "shard " + std::to_string(o.shard) + "/" + std::to_string(o.shards) + " "
                   : "sweep ";
  const StopOnSignals stop;
  std::unique_ptr<EmbreeTracer> tracer;  // of scene `built`, shared by its consecutive views
  std::size_t built = in.scenes.size();
  for (std::size_t s = 0; s < in.views.size(); ++s) {
    const SweepView& view = in.views[s];
    report.runs.push_back({in.files[view.scene], 0.0, 0.0});
    std::vector<int> pending;
    for (int t : mine) {
      if (plan.tiles[t].view != static_cast<int>(s)) continue;
      const fs::path path = dir / tileFileName(id.views[s], plan.tiles[t].index);
      if (haveTile(path, id, plan.tiles[t])) {
        ++report.reused;
      } else {
        pending.push_back(t);
      }
    }
    if (pending.empty() || stop.signal() != 0) continue;
    const auto build_start = std::chrono::steady_clock::now();
    if (built != view.scene) {
      tracer.reset();
      tracer = std::make_unique<EmbreeTracer>(in.scenes[view.scene]);
      built = view.scene;
    }
    settings.view_key = viewStreamKey(view.name);
    const auto trace_start = std::chrono::steady_clock::now();
    report.runs[s].build_seconds = std::chrono::duration<double>(trace_start - build_start).count();
    std::uint64_t pixels = 0;
    for (int t : pending) pixels += plan.tiles[t].rect.pixels();
    Progress bar(prefix + id.views[s], pixels, o.progress);
    std::atomic<std::size_t> traced{0};
    std::atomic<std::uint64_t> rays{0};
    tbb::parallel_for(std::size_t{0}, pending.size(), [&](std::size_t k) {
      if (stop.signal() != 0) return;
      const Tile& tile = plan.tiles[pending[k]];
      const EscapeImage image =
          traceEscapeImage(*tracer, view.camera, o.width, o.height, tile.rect, settings, "", false);
      writeTile(dir / tileFileName(id.views[s], tile.index),
                makeTile(image, id.key, id.views[s], tile.index, tile.rect));
      rays += image.rays;
      ++traced;
      bar.add(tile.rect.pixels());
    });
    if (stop.signal() == 0) {
      bar.finish();
    } else {
      bar.abandon();
    }
    report.runs[s].trace_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - trace_start).count();
    report.traced += traced.load();
    report.rays += rays.load();
  }
  report.signal = stop.signal();
  return report;
}

[[noreturn]] void throwInterrupted(const SweepOptions& o, const TraceReport& report,
                                   std::size_t total, const fs::path& dir) {
  const std::string command =
      o.command_line.empty() ? "the same gtbake sweep command" : o.command_line;
  throw SweepInterrupted("interrupted by " + signalName(report.signal) + ": " +
                             std::to_string(report.traced + report.reused) + " of " +
                             std::to_string(total) + " tiles are saved in " + dir.string() +
                             "; to resume, run again: " + command +
                             (o.resume ? "" : " (or add --resume)"),
                         report.signal);
}

// A finished shard: its manifest, and one line on stdout.
SweepResult finishShard(const SweepOptions& o, const SweepIdentity& id, const TilePlan& plan,
                        const std::vector<int>& mine, TraceReport report, int threads,
                        double seconds) {
  ShardManifest manifest;
  manifest.identity = id;
  for (ViewRun& run : report.runs) run.gltf = relativePath(run.gltf, o.out);
  manifest.runs = report.runs;
  manifest.shard = o.shard;
  manifest.shards = o.shards;
  manifest.tiles = mine;
  manifest.threads = threads;
  manifest.seconds = seconds;
  writeShardManifest(o.out, manifest, plan);
  std::printf(
      "shard %d/%d: %zu of %zu tiles of %zu views (%zu traced now, %zu checkpointed), "
      "%.1f Mrays in %.2f s -> %s\n",
      o.shard, o.shards, mine.size(), plan.tiles.size(), id.views.size(), report.traced,
      report.reused, 1e-6 * static_cast<double>(report.rays), seconds,
      (o.out / "shard.json").c_str());
  SweepResult result;
  result.seconds = seconds;
  result.rays = report.rays;
  return result;
}

}  // namespace

std::string gbufferRadiusList(const std::vector<double>& radii) {
  return formatNumberList(radii);
}

SweepResult runSweep(const SweepOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  validateOptions(options);
  checkImageMemory(options);
  const ThreadLimit threads(options.threads);
  const std::vector<fs::path> files = resolveSceneFiles(options.scenes);
  const SweepInputs inputs = loadScenes(files, options);
  const SweepIdentity id = describeSweep(options, inputs);
  const bool sharded = options.shards > 0;
  const TilePlan plan = planTiles(static_cast<int>(inputs.views.size()), options.width,
                                  options.height, sharded ? options.shards : 1);
  const std::vector<int> mine = plan.tilesOfShard(sharded ? options.shard : 0);
  const OutputLock lock(options.out);  // tiles, shard and sweep sets alike (output_lock.h)
  ensureWritableDirectory(options.out);
  const fs::path dir = openTileDirectory(options, id);

  const TraceReport report = traceTiles(options, inputs, id, plan, mine, dir);
  if (report.signal != 0) throwInterrupted(options, report, mine.size(), dir);
  if (report.reused > 0 && options.progress) {
    std::fprintf(stderr, "sweep: resumed: %zu of %zu tiles were checkpointed in %s\n",
                 report.reused, mine.size(), dir.c_str());
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (sharded) return finishShard(options, id, plan, mine, report, threads.threads(), seconds);

  const SweepResult result =
      writeSweepOutputs(options.out, id, plan, report.runs, threads.threads(), [&](int t) {
        return readTile(dir / tileFileName(id.views[plan.tiles[t].view], plan.tiles[t].index));
      });
  std::error_code ec;
  fs::remove_all(dir, ec);  // the outputs are complete; a leftover checkpoint only costs space
  return result;
}

}  // namespace gtbake
