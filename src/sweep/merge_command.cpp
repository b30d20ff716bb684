// `gtbake merge` in named steps: read the manifests, check they describe one sweep, check the
// tiles cover the plan exactly once, verify the tile files, write the outputs.
#include "sweep/merge_command.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_lock.h"
#include "sweep/shard_manifest.h"
#include "sweep/sweep_output.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

struct Shard {
  fs::path dir;
  ShardManifest manifest;
};

std::vector<Shard> readShards(const MergeOptions& o) {
  if (o.shards.empty()) throw Error("no shards given: pass the shard directories to merge");
  if (o.out.empty()) throw Error("no output directory given: pass --out DIR");
  std::vector<Shard> shards;
  for (const fs::path& dir : o.shards) shards.push_back({dir, readShardManifest(dir)});
  std::stable_sort(shards.begin(), shards.end(), [](const Shard& a, const Shard& b) {
    return a.manifest.shard < b.manifest.shard;
  });
  return shards;
}

// The first setting (in sweep.json's order) whose values differ, for the error message.
std::string firstDifference(const SweepIdentity& a, const SweepIdentity& b) {
  if (a.version != b.version) return "gtbake version " + a.version + " vs " + b.version;
  if (a.views != b.views) return "view lists";
  if (a.camera != b.camera) return "--camera '" + a.camera + "' vs '" + b.camera + "'";
  for (std::size_t s = 0; s < a.views.size(); ++s) {
    if (a.view_sha256[s] != b.view_sha256[s]) {
      return "contents of scene " + a.view_scene[s] + " (view " + a.views[s] + ")";
    }
  }
  for (const auto& [key, value] : a.settings.items()) {
    if (!b.settings.contains(key) || b.settings[key] != value) {
      return key + " " + value.dump() + " vs " +
             (b.settings.contains(key) ? b.settings[key].dump() : std::string("(none)"));
    }
  }
  return "settings";
}

void checkOneSweep(const std::vector<Shard>& shards) {
  const Shard& first = shards.front();
  for (const Shard& shard : shards) {
    if (shard.manifest.identity.key != first.manifest.identity.key) {
      throw Error("shards of different sweeps: " + first.dir.string() + " and " +
                  shard.dir.string() + " differ in " +
                  firstDifference(first.manifest.identity, shard.manifest.identity));
    }
    if (shard.manifest.shards != first.manifest.shards) {
      throw Error("shards of different partitions: " + first.dir.string() + " is of " +
                  std::to_string(first.manifest.shards) + " shards, " + shard.dir.string() +
                  " of " + std::to_string(shard.manifest.shards));
    }
  }
}

// Names up to four tiles of a list ("cavity:3, cavity:17, … (12 in all)").
std::string nameTiles(const TilePlan& plan, const SweepIdentity& id,
                      const std::vector<int>& tiles) {
  std::string names;
  for (std::size_t k = 0; k < tiles.size() && k < 4; ++k) {
    const Tile& tile = plan.tiles[tiles[k]];
    names += (k ? ", " : "") + id.views[tile.view] + ":" + std::to_string(tile.index);
  }
  if (tiles.size() > 4) names += ", ... (" + std::to_string(tiles.size()) + " in all)";
  return names;
}

// Which shard holds each plan tile; overlapping or missing tiles are an error naming them.
std::vector<int> checkCoverage(const std::vector<Shard>& shards, const TilePlan& plan) {
  const SweepIdentity& id = shards.front().manifest.identity;
  std::vector<int> owner(plan.tiles.size(), -1);
  std::vector<int> overlapping;
  for (std::size_t k = 0; k < shards.size(); ++k) {
    for (int t : shards[k].manifest.tiles) {
      if (t < 0 || t >= static_cast<int>(plan.tiles.size())) {
        throw Error("corrupt shard " + shards[k].dir.string() + ": tile " + std::to_string(t) +
                    " is not in the plan");
      }
      if (owner[t] >= 0) {
        overlapping.push_back(t);
      } else {
        owner[t] = static_cast<int>(k);
      }
    }
  }
  if (!overlapping.empty()) {
    throw Error("overlapping shards: tiles " + nameTiles(plan, id, overlapping) +
                " are in more than one shard directory");
  }
  std::vector<int> missing;
  for (std::size_t t = 0; t < owner.size(); ++t) {
    if (owner[t] < 0) missing.push_back(static_cast<int>(t));
  }
  if (!missing.empty()) {
    throw Error("missing tiles " + nameTiles(plan, id, missing) +
                ": merge every shard of the sweep");
  }
  return owner;
}

}  // namespace

SweepResult runMerge(const MergeOptions& options) {
  const std::vector<Shard> shards = readShards(options);
  std::error_code ec;
  const bool existed = fs::exists(options.out, ec);
  const OutputLock lock(options.out);  // for the whole run (output_lock.h)
  checkOneSweep(shards);
  const ShardManifest& first = shards.front().manifest;
  const SweepIdentity& id = first.identity;
  const TilePlan plan =
      planTiles(static_cast<int>(id.views.size()), id.width, id.height, first.shards);
  const std::vector<int> owner = checkCoverage(shards, plan);
  for (const Shard& shard : shards) checkShardFiles(shard.dir, shard.manifest, plan);

  std::vector<ViewRun> runs(id.views.size());
  int threads = 0;
  for (const Shard& shard : shards) {
    threads = std::max(threads, shard.manifest.threads);
    for (std::size_t s = 0; s < runs.size(); ++s) {
      runs[s].build_seconds += shard.manifest.runs[s].build_seconds;
      runs[s].trace_seconds += shard.manifest.runs[s].trace_seconds;
    }
  }
  for (std::size_t s = 0; s < runs.size(); ++s) {
    runs[s].gltf = (shards.front().dir / first.runs[s].gltf).lexically_normal();
  }
  std::printf("merge: %zu shards of %d (", shards.size(), first.shards);
  for (std::size_t k = 0; k < shards.size(); ++k) {
    std::printf("%s%d: %s, %zu tiles", k ? "; " : "", shards[k].manifest.shard,
                shards[k].dir.c_str(), shards[k].manifest.tiles.size());
  }
  std::printf("), %zu tiles of %zu views -> %s\n", plan.tiles.size(), id.views.size(),
              options.out.c_str());
  try {
    // Each tile file is checked against its shard's SHA-256 as it is read; the outputs are one
    // output set, so a corrupt tile found half-way leaves nothing behind.
    return writeSweepOutputs(options.out, id, plan, runs, threads, [&](int t) {
      const std::string name = tilePath(id, plan, t);
      return decodeTile(shards[owner[t]].manifest.files.readVerified(name),
                        (shards[owner[t]].dir / name).string());
    });
  } catch (const Error&) {
    if (!existed) fs::remove(options.out, ec);  // only if still empty
    throw;
  }
}

}  // namespace gtbake
