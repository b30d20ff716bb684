#include "sweep/shard_manifest.h"

#include "common/atomic_file.h"
#include "common/error.h"
#include "sweep/sha256.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormat = "gtbake-shard 1";

}  // namespace

void writeShardManifest(const fs::path& dir, ShardManifest manifest, const TilePlan& plan) {
  const SweepIdentity& id = manifest.identity;
  manifest.files.clear();
  for (int t : manifest.tiles) {
    const Tile& tile = plan.tiles[t];
    const std::string name =
        std::string(kTileDirectory) + "/" + tileFileName(id.scenes[tile.scene], tile.index);
    const std::string bytes = readFile(dir / name);
    manifest.files.push_back({name, bytes.size(), sha256Hex(bytes)});
  }
  nlohmann::ordered_json j;
  j["format"] = kFormat;
  j["gtbake_version"] = id.version;
  j["key"] = id.key;
  j["settings"] = id.settings;
  j["attributes"] = id.attributes;
  j["width"] = id.width;
  j["height"] = id.height;
  j["tile_side"] = kTileSide;
  nlohmann::ordered_json scenes = nlohmann::ordered_json::array();
  for (std::size_t s = 0; s < id.scenes.size(); ++s) {
    scenes.push_back({{"name", id.scenes[s]},
                      {"sha256", id.scene_sha256[s]},
                      {"gltf", manifest.runs[s].gltf.string()},
                      {"build_seconds", manifest.runs[s].build_seconds},
                      {"trace_seconds", manifest.runs[s].trace_seconds}});
  }
  j["scenes"] = std::move(scenes);
  j["shard"] = manifest.shard;
  j["shards"] = manifest.shards;
  j["tiles"] = manifest.tiles;
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const ShardFile& f : manifest.files) {
    files.push_back({{"name", f.name}, {"size", f.size}, {"sha256", f.sha256}});
  }
  j["files"] = std::move(files);
  j["threads"] = manifest.threads;
  j["seconds"] = manifest.seconds;
  writeFileAtomically(dir / "shard.json", j.dump(2) + "\n");
}

ShardManifest readShardManifest(const fs::path& dir) {
  const fs::path path = dir / "shard.json";
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw Error(dir.string() + " has no shard.json: not a shard directory, or its shard did not " +
                "finish (run its gtbake sweep --shard command again to resume it)");
  }
  ShardManifest m;
  try {
    const nlohmann::ordered_json j = nlohmann::ordered_json::parse(readFile(path));
    if (j.at("format").get<std::string>() != kFormat) {
      throw Error(path.string() + " is not a " + std::string(kFormat) + " manifest");
    }
    SweepIdentity& id = m.identity;
    id.version = j.at("gtbake_version").get<std::string>();
    id.key = j.at("key").get<std::string>();
    id.settings = j.at("settings");
    id.attributes = j.at("attributes").get<std::map<std::string, std::string>>();
    id.width = j.at("width").get<int>();
    id.height = j.at("height").get<int>();
    if (j.at("tile_side").get<int>() != kTileSide) {
      throw Error(path.string() + " was cut into tiles of another size (other gtbake version)");
    }
    for (const auto& s : j.at("scenes")) {
      id.scenes.push_back(s.at("name").get<std::string>());
      id.scene_sha256.push_back(s.at("sha256").get<std::string>());
      m.runs.push_back({fs::path(s.at("gltf").get<std::string>()),
                        s.at("build_seconds").get<double>(), s.at("trace_seconds").get<double>()});
    }
    m.shard = j.at("shard").get<int>();
    m.shards = j.at("shards").get<int>();
    m.tiles = j.at("tiles").get<std::vector<int>>();
    for (const auto& f : j.at("files")) {
      m.files.push_back({f.at("name").get<std::string>(), f.at("size").get<std::uint64_t>(),
                         f.at("sha256").get<std::string>()});
    }
    m.threads = j.at("threads").get<int>();
    m.seconds = j.at("seconds").get<double>();
  } catch (const nlohmann::json::exception& e) {
    throw Error("corrupt shard manifest " + path.string() + ": " + e.what());
  }
  SweepIdentity check = m.identity;
  sealIdentity(&check);
  if (check.key != m.identity.key) {
    throw Error("corrupt shard manifest " + path.string() +
                ": its key does not match its settings");
  }
  if (m.shards < 1 || m.shard < 0 || m.shard >= m.shards || m.files.size() != m.tiles.size()) {
    throw Error("corrupt shard manifest " + path.string() + ": bad shard index or file list");
  }
  return m;
}

void verifyShardFiles(const fs::path& dir, const ShardManifest& manifest) {
  for (const ShardFile& f : manifest.files) {
    const fs::path path = dir / f.name;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
      throw Error("corrupt shard " + dir.string() + ": " + f.name + " is missing");
    const std::string bytes = readFile(path);
    if (bytes.size() != f.size || sha256Hex(bytes) != f.sha256) {
      throw Error("corrupt shard " + dir.string() + ": " + f.name +
                  " does not match the SHA-256 in its shard.json");
    }
  }
}

}  // namespace gtbake
