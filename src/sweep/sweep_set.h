// The sweep's own reader of what it writes: sweep.json (docs/sweep.md "Outputs") parsed and
// validated once, into typed settings and one entry per view, for every stage that reads a sweep
// (fit, screen-ao, tune, validate-gtso). No tracer here: this library links no Embree.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/output_set.h"

namespace gtbake {

// sweep.json "settings": what the sweep traced. Lists are empty when the sweep traced none.
struct SweepSettings {
  int spp = 0;
  int width = 0;   // the default image side; a view may record its own
  int height = 0;  //
  int bounces = 0;
  std::optional<double> radius;            // sky beyond this distance; none = unbounded
  std::optional<std::uint64_t> seed;       // absent in sweeps that predate it
  std::vector<double> albedos;             // ρ of the G### channels: distinct hundredths in (0, 1]
  std::vector<double> specular_roughness;  // r_p of the S### channels: distinct hundredths
  int specular_spp = 0;                    // 0 without specular channels
  std::vector<double> gbuffer_radii;       // radii of the A_R channels, metres, ascending
  bool transfer = false;  // T<k>_SH<i> channels (docs/sweep.md "Transfer"); absent: false
};

// One image of the sweep (a sweep.json "views" entry: a view of a scene).
struct SweepView {
  std::string name;   // the view: its outputs are named after it (the EXR's stem)
  std::string scene;  // the scene it shows: the cluster of scene-level uncertainties (its own
                      // name when the entry has no "scene": the image is its own scene)
  std::string type;   // the scene type (its scene when absent)
  std::string file;   // the EXR, a plain file name inside the sweep directory
  std::string gltf;   // the scene file traced (empty when not recorded)
  int width = 0;
  int height = 0;
  std::optional<std::int64_t> unmasked_pixels;
  nlohmann::json camera;  // as written (camera_json.h reads it); null when not recorded
};

struct SweepSet {
  std::filesystem::path dir;
  std::string where;        // "<dir>/sweep.json", for messages
  OutputManifest manifest;  // every file read from the sweep must match it (output_set.h)
  std::string version;      // gtbake_version of the sweep that wrote it
  SweepSettings settings;
  std::vector<SweepView> views;  // at least one; names and files distinct
};

// Reads <dir>/sweep.json through the sweep's manifest and validates every field it returns
// (docs/limits.md §Values: integers within what `gtbake sweep` accepts, lists as the sweep
// writes them, each view's name and file once, every file inside <dir>). Throws one line.
SweepSet readSweepSet(const std::filesystem::path& dir);

// The suffix of the near-field channels at radius R: "_R" and R as %g with '.' written 'p'
// (nearFieldChannelName appends it to a channel's name), e.g. 1 -> "_R1".
std::string nearFieldSuffix(double radius);

// The names of the sweep's EXR channels (docs/sweep.md, "Outputs"), for every reader of them.
// G(ρ) channel name, e.g. 0.5 -> "G050".
std::string albedoChannelName(double albedo);
// The near-field channel of an unbounded one at G-buffer radius R: the name, "_R" and the radius
// in metres as %g with '.' written 'p' (EXR reads '.' as a layer separator), e.g. ("G050", 1) ->
// "G050_R1", ("A", 0.25) -> "A_R0p25" (docs/sweep.md, "Near-field truth").
std::string nearFieldChannelName(const std::string& name, double radius);
// A_R channel name of a G-buffer radius: nearFieldChannelName("A", radius).
std::string gbufferRadiusChannelName(double radius);
// S(r_p) channel name, e.g. 0.25 -> "S025".
std::string specularChannelName(double roughness);
// Transfer channel of bounce k and SH coefficient i, "T<k>_SH<i>", e.g. (1, 4) -> "T1_SH4".
std::string transferChannelName(int k, int i);

// The suffix of the channels holding the truth at `radius` (none: "", the unbounded truth), after
// checking that the sweep traced that G-buffer radius (settings gbuffer_radii): otherwise a
// one-line gtbake::Error naming the radii it holds.
std::string truthChannelSuffix(const SweepSet& set, std::optional<double> radius);

}  // namespace gtbake
