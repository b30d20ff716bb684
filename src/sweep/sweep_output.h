// The outputs of a sweep, written from its tiles: one path for `gtbake sweep`, for a resumed
// sweep and for `gtbake merge`, so the three write the same bytes (docs/reproducibility.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sweep/sweep_command.h"
#include "sweep/tile_plan.h"
#include "sweep/tile_store.h"

namespace gtbake {

// What every shard of one sweep shares and what its outputs record besides pixels.
struct SweepIdentity {
  std::string version;                            // gtbake version that traced it
  nlohmann::ordered_json settings;                // sweep.json "settings" without "threads"
  std::map<std::string, std::string> attributes;  // EXR attributes without "gtbake.scene"
  // Per view (one image each), in sweep order (docs/scenes.md "Vocabulary"): its name (the glTF
  // stem, or <stem>_v<k> for automatic views), its scene (the glTF stem: the cluster the views of
  // one file share) and its scene type (the glTF's "gtbake_type", else the scene).
  std::vector<std::string> views;
  std::vector<std::string> view_scene;
  std::vector<std::string> view_type;
  // Per view, of the scene it shows: GltfReadInfo::input_sha256 (the glTF and its buffers), the
  // triangle count; and cameraJson of the view's camera.
  std::vector<std::string> view_sha256;
  std::vector<std::uint64_t> view_triangles;
  std::vector<nlohmann::ordered_json> view_cameras;
  int width = 0;
  int height = 0;
  std::string camera;  // --camera ("" = each glTF's first)
  std::string key;     // SHA-256 of all of the above and kTileSide: equal keys, same tiles
};

// Fills `key` from the other fields.
void sealIdentity(SweepIdentity* identity);

// Per view, what the run that traced it measured (summed over shards by a merge).
struct ViewRun {
  std::filesystem::path gltf;  // its scene's file (any form; recorded relative to the output)
  double build_seconds = 0.0;
  double trace_seconds = 0.0;
};

// Writes <out>/<view>.exr, the previews and <out>/sweep.json from the tiles of every view
// (`load(t)` gives plan tile t), prints the summary table and returns the totals.
SweepResult writeSweepOutputs(const std::filesystem::path& out, const SweepIdentity& identity,
                              const TilePlan& plan, const std::vector<ViewRun>& runs, int threads,
                              const std::function<TileData(int)>& load);

}  // namespace gtbake
