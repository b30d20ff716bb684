// `gtbake merge --out DIR SHARD_DIR...`: the sweep directory of an unsharded run, from the shards
// of `gtbake sweep --shard I/N` (docs/cluster.md).
#pragma once

#include <filesystem>
#include <vector>

#include "sweep/sweep_command.h"

namespace gtbake {

struct MergeOptions {
  std::vector<std::filesystem::path> shards;  // shard directories, in any order
  std::filesystem::path out;
};

// Checks that the shards are of one sweep (settings, seed, scene contents, gtbake version), that
// their tiles cover the plan exactly once and that every tile file matches its manifest's
// SHA-256; then writes the outputs an unsharded `gtbake sweep` writes (the same EXR and PNG bytes,
// the same sweep.json apart from timings, which are summed over the shards, and "threads", the
// largest count a shard used). Every check comes before anything is written; each failure is a
// one-line gtbake::Error naming the shard, setting or tiles at fault.
SweepResult runMerge(const MergeOptions& options);

}  // namespace gtbake
