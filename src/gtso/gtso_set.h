// The reader of `gtbake gtso`'s output set (docs/gtso.md §4): gtso.json and its float tables,
// verified against the set's manifest and validated into plain structs, for the stages that read
// it (encode, validate-gtso, export). Every problem is one gtbake::Error line.
#pragma once

#include <array>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace gtbake {

// A table axis as gtso.json lists it. The quantities and their maps are fixed by the runtime
// lookup code (runtime/gtso_runtime.h) that the generated files carry; export rejects a
// gtso.json whose axes or axis constants differ from it.
struct GtsoAxis {
  std::string name;      // "x", "y", "z", "w"
  std::string quantity;  // kGtso3DAxisInfo / kGtso4DAxisInfo
};

struct GtsoTable {
  std::string file;             // e.g. "gtso3d.f32"
  std::vector<int> dims;        // per axis, x fastest: 3 (3D) or 4 (4D) entries
  std::vector<GtsoAxis> axes;   // same order as dims
  std::array<int, 3> volume{};  // texture extent: 4D folds z and w into depth = dims[2]·dims[3]
  std::vector<float> values;    // volume[0]·volume[1]·volume[2] floats, x fastest
  nlohmann::json meta;          // the table's gtso.json object (samples, errors, …) verbatim
};

struct GtsoInput {
  GtsoTable table3d;
  GtsoTable table4d;
  double u = 0.0;     // cone-aperture constant: cos αs = u^(α²/2)
  double u_se = 0.0;  // its standard error
  // Closed-form S3 (gtso.json closed_form.coefficients): kGtsoS3ClosedFormCoeffs values.
  std::vector<double> s3_closed_form;
  nlohmann::json json;             // gtso.json verbatim (provenance)
  std::filesystem::path json_dir;  // the directory it was read from
  // Set by export from validate_gtso.json (applyValidateGtsoU): u fitted to path-traced S
  // replaces the table fit; validate_gtso is that file verbatim (null: u is gtso.json's table fit).
  double u_low = 0.0, u_high = 0.0;  // its scene-level 95% interval (validate_gtso.json)
  nlohmann::json validate_gtso;
};

GtsoInput readGtsoInput(const std::filesystem::path& dir);

}  // namespace gtbake
