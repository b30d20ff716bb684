// A shard directory's record: <dir>/shard.json (the sweep's identity, the shard index, the tiles
// it covers, its timings) and the output-set manifest <dir>/shard.manifest.json over shard.json
// and every tile file (sizes, SHA-256; output_set.h), written last by `gtbake sweep --shard I/N`.
// A shard directory without that manifest did not finish; `gtbake merge` verifies every file it
// reads against it (docs/cluster.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "common/output_set.h"
#include "sweep/sweep_output.h"

namespace gtbake {

// The directory, inside a sweep's output or shard directory, that holds its tile files.
inline constexpr const char* kTileDirectory = "sweep-tiles";
// The output-set command name of a shard directory ("shard.manifest.json").
inline constexpr const char* kShardSet = "shard";

struct ShardManifest {
  SweepIdentity identity;
  std::vector<ViewRun> runs;  // per view: its glTF (relative to the shard directory), timings
  int shard = 0;
  int shards = 1;
  std::vector<int> tiles;  // plan indices of the tiles covered, ascending
  int threads = 0;
  double seconds = 0.0;
  OutputManifest files;  // filled by readShardManifest: verifies each file read
};

// The name of plan tile t's file inside a shard or sweep directory ("sweep-tiles/…").
std::string tilePath(const SweepIdentity& identity, const TilePlan& plan, int t);

// Writes <dir>/shard.json, then seals shard.json and the tiles' files as the output set.
void writeShardManifest(const std::filesystem::path& dir, const ShardManifest& manifest,
                        const TilePlan& plan);

// Reads and checks <dir>/shard.json through its output set (one-line gtbake::Error if missing,
// unfinished, malformed or not matching its key).
ShardManifest readShardManifest(const std::filesystem::path& dir);

// Checks that every tile the shard covers is in the plan and in its output set, with a file of
// the recorded size. The tiles' SHA-256 are checked as they are read (files.readVerified).
void checkShardFiles(const std::filesystem::path& dir, const ShardManifest& manifest,
                     const TilePlan& plan);

// Removes a shard directory's record (before its tiles are replaced by another sweep's).
void removeShardManifest(const std::filesystem::path& dir);

}  // namespace gtbake
