// <shard dir>/shard.json: what `gtbake merge` needs to trust a shard (docs/cluster.md). Written
// last and atomically by `gtbake sweep --shard I/N`, so a shard directory without it did not
// finish. Lists every tile file with its size and SHA-256; readers verify them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sweep/sweep_output.h"

namespace gtbake {

// The directory, inside a sweep's output or shard directory, that holds its tile files.
inline constexpr const char* kTileDirectory = "sweep-tiles";

struct ShardFile {
  std::string name;  // relative to the shard directory
  std::uint64_t size = 0;
  std::string sha256;
};

struct ShardManifest {
  SweepIdentity identity;
  std::vector<SceneRun> runs;  // per scene: glTF (relative to the shard directory), build time
  int shard = 0;
  int shards = 1;
  std::vector<int> tiles;  // plan indices of the tiles covered, ascending
  std::vector<ShardFile> files;
  int threads = 0;
  double seconds = 0.0;
};

// Hashes the tile files of `manifest.tiles` into `manifest.files` and writes <dir>/shard.json.
void writeShardManifest(const std::filesystem::path& dir, ShardManifest manifest,
                        const TilePlan& plan);

// Reads <dir>/shard.json (one-line gtbake::Error if missing or malformed); does not read tiles.
ShardManifest readShardManifest(const std::filesystem::path& dir);

// Checks each listed file's size and SHA-256; throws naming the first file that differs.
void verifyShardFiles(const std::filesystem::path& dir, const ShardManifest& manifest);

}  // namespace gtbake
