#include "sweep/shard_manifest.h"

#include <algorithm>
#include <set>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/input_limits.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

// 2: the per-view list is "views" (it was "scenes"; docs/scenes.md "Vocabulary").
constexpr const char* kFormat = "gtbake-shard 2";

}  // namespace

std::string tilePath(const SweepIdentity& identity, const TilePlan& plan, int t) {
  const Tile& tile = plan.tiles[t];
  return std::string(kTileDirectory) + "/" + tileFileName(identity.views[tile.view], tile.index);
}

void writeShardManifest(const fs::path& dir, const ShardManifest& manifest, const TilePlan& plan) {
  const SweepIdentity& id = manifest.identity;
  nlohmann::ordered_json j;
  j["format"] = kFormat;
  j["gtbake_version"] = id.version;
  j["key"] = id.key;
  j["settings"] = id.settings;
  j["attributes"] = id.attributes;
  j["width"] = id.width;
  j["height"] = id.height;
  j["camera"] = id.camera;
  j["tile_side"] = kTileSide;
  nlohmann::ordered_json views = nlohmann::ordered_json::array();
  for (std::size_t s = 0; s < id.views.size(); ++s) {
    views.push_back({{"name", id.views[s]},
                     {"scene", id.view_scene[s]},
                     {"type", id.view_type[s]},
                     {"sha256", id.view_sha256[s]},
                     {"triangles", id.view_triangles[s]},
                     {"camera", id.view_cameras[s]},
                     {"gltf", manifest.runs[s].gltf.string()},
                     {"build_seconds", manifest.runs[s].build_seconds},
                     {"trace_seconds", manifest.runs[s].trace_seconds}});
  }
  j["views"] = std::move(views);
  j["shard"] = manifest.shard;
  j["shards"] = manifest.shards;
  j["tiles"] = manifest.tiles;
  j["threads"] = manifest.threads;
  j["seconds"] = manifest.seconds;
  // shard.json and the tiles switch in as one set (output_set.h); the tiles are already in place.
  OutputSet set(dir, kShardSet);
  set.add("shard.json", j.dump(2) + "\n");
  for (int t : manifest.tiles) set.adopt(tilePath(id, plan, t));
  set.setSettings(id.settings);
  set.commit();
}

void removeShardManifest(const fs::path& dir) {
  std::error_code ec;
  fs::remove(dir / manifestFileName(kShardSet), ec);
  fs::remove(dir / "shard.json", ec);
}

namespace {

// The views of shard.json: names, their scenes' hashes and cameras as written (`ordered`), counts
// and times range-checked (`plain`, the same text).
void readShardViews(const nlohmann::ordered_json& ordered, const nlohmann::json& plain,
                    const std::string& at, ShardManifest* m) {
  SweepIdentity& id = m->identity;
  if (ordered.size() > static_cast<std::size_t>(kMaxSweepViews)) {
    throw Error(at + ": more than " + std::to_string(kMaxSweepViews) + " views");
  }
  std::set<std::string> names;
  for (std::size_t k = 0; k < ordered.size(); ++k) {
    const auto& s = ordered.at(k);
    const nlohmann::json& p = plain.at(k);
    id.views.push_back(s.at("name").get<std::string>());
    // merge names each view's outputs by its name: each once.
    if (!names.insert(id.views.back()).second) {
      throw Error(at + ": view '" + id.views.back() + "' is listed twice");
    }
    id.view_scene.push_back(s.at("scene").get<std::string>());
    id.view_type.push_back(s.at("type").get<std::string>());
    id.view_sha256.push_back(s.at("sha256").get<std::string>());
    id.view_triangles.push_back(static_cast<std::uint64_t>(
        jsonInteger(p, "triangles", 1, static_cast<std::int64_t>(limitValue(kMaxTriangles)), at)));
    id.view_cameras.push_back(s.at("camera"));
    m->runs.push_back({fs::path(s.at("gltf").get<std::string>()),
                       jsonNumber(p, "build_seconds", 0.0, kMaxRecordedSeconds, at),
                       jsonNumber(p, "trace_seconds", 0.0, kMaxRecordedSeconds, at)});
  }
}

}  // namespace

ShardManifest readShardManifest(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_regular_file(dir / manifestFileName(kShardSet), ec)) {
    throw Error(dir.string() + " has no " + manifestFileName(kShardSet) +
                ": not a shard directory, or its shard did not finish (run its gtbake sweep "
                "--shard command again to resume it)");
  }
  const std::string where = "corrupt shard " + dir.string() + ": ";
  ShardManifest m;
  m.files = readOutputSet(dir, kShardSet);
  const std::string text = m.files.readVerified("shard.json");
  // Every number is range-checked where it is read (docs/limits.md §Values); the settings and
  // cameras are kept in their written order, which the key hashes.
  const nlohmann::json plain = parseJsonText(text, (dir / "shard.json").string());
  const std::string at = where + "shard.json";
  try {
    const nlohmann::ordered_json j = nlohmann::ordered_json::parse(text);
    if (j.at("format").get<std::string>() != kFormat) {
      throw Error(where + "shard.json is not a " + std::string(kFormat) +
                  " record (another gtbake version wrote it: run its gtbake sweep --shard "
                  "command again)");
    }
    SweepIdentity& id = m.identity;
    id.version = j.at("gtbake_version").get<std::string>();
    id.key = j.at("key").get<std::string>();
    id.settings = j.at("settings");
    id.attributes = j.at("attributes").get<std::map<std::string, std::string>>();
    id.width = static_cast<int>(jsonInteger(plain, "width", 1, kMaxImageSide, at));
    id.height = static_cast<int>(jsonInteger(plain, "height", 1, kMaxImageSide, at));
    id.camera = j.at("camera").get<std::string>();
    if (jsonInteger(plain, "tile_side", 1, kMaxImageSide, at) != kTileSide) {
      throw Error(where + "cut into tiles of another size (by another gtbake version)");
    }
    readShardViews(j.at("views"), plain.at("views"), at, &m);
    m.shards = static_cast<int>(jsonInteger(plain, "shards", 1, kMaxSweepShards, at));
    m.shard = static_cast<int>(jsonInteger(plain, "shard", 0, m.shards - 1, at));
    m.tiles = j.at("tiles").get<std::vector<int>>();
    if (!std::is_sorted(m.tiles.begin(), m.tiles.end()) ||
        std::adjacent_find(m.tiles.begin(), m.tiles.end()) != m.tiles.end()) {
      throw Error(where + "its tile list is not ascending without repeats");
    }
    m.threads = static_cast<int>(jsonInteger(plain, "threads", 0, 1 << 16, at));
    m.seconds = jsonNumber(plain, "seconds", 0.0, kMaxRecordedSeconds, at);
  } catch (const nlohmann::json::exception& e) {
    throw Error(where + "malformed shard.json (" + e.what() + ")");
  }
  SweepIdentity check = m.identity;
  sealIdentity(&check);
  if (check.key != m.identity.key) throw Error(where + "its key does not match its settings");
  return m;
}

void checkShardFiles(const fs::path& dir, const ShardManifest& m, const TilePlan& plan) {
  const std::string where = "corrupt shard " + dir.string() + ": ";
  std::error_code ec;
  for (int t : m.tiles) {
    if (t < 0 || t >= static_cast<int>(plan.tiles.size())) {
      throw Error(where + "tile " + std::to_string(t) + " is not in the plan");
    }
    const std::string name = tilePath(m.identity, plan, t);
    const OutputFile* file = m.files.find(name);
    if (file == nullptr) throw Error(where + name + " is not in its manifest");
    if (!fs::is_regular_file(dir / name, ec) || fs::file_size(dir / name, ec) != file->size) {
      throw Error(where + name + " is missing or has another size than its manifest says");
    }
  }
}

}  // namespace gtbake
