// The inputs of `gtbake export`: fit.json from `gtbake fit` and the directory of `gtbake gtso`
// (SPEC §1.3–§1.5), read and validated into plain structs. Every problem is one gtbake::Error line.
#pragma once

#include <array>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace gtbake {

// The axis quantities a GTSO table may use; each axis is linear in its quantity between min and
// max. Families: A ∈ {A, cos_alpha_v = √(1 − A), alpha_v}, β ∈ {cos_beta, beta},
// roughness ∈ {r_p, alpha = r_p²}, θo ∈ {cos_theta_o, theta_o}; angles in radians.
enum class AxisFamily { kAmbient, kBeta, kRoughness, kThetaO };
bool isAxisQuantity(const std::string& quantity);
AxisFamily axisFamily(const std::string& quantity);

struct GtsoAxis {
  std::string name;      // "x", "y", "z", "w"
  std::string quantity;  // from the vocabulary above
  double min = 0.0;      // quantity at texel 0
  double max = 1.0;      // quantity at texel N − 1
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
  double u = 0.0;       // cone-aperture constant: cos αs = u^(α²/2)
  double u_se = 0.0;    // its standard error
  nlohmann::json json;  // gtso.json verbatim (provenance)
  // Set by applyValidateGtsoU: u fitted to path-traced S (validate_gtso.json) replaces the table
  // fit; validate_gtso is that file verbatim (null: u is gtso.json's table fit).
  double u_low = 0.0, u_high = 0.0;  // its 5% profile interval
  nlohmann::json validate_gtso;
};

struct FitInput {
  std::array<double, 6> linear{};     // a1, a0, b1, b0, c1, c0 (G = a·A³ − b·A² + c·A)
  std::array<double, 6> linear_se{};  // standard errors, same order
  nlohmann::json json;                // fit.json verbatim (provenance)
};

GtsoInput readGtsoInput(const std::filesystem::path& dir);
FitInput readFitInput(const std::filesystem::path& file);

// Takes u and u_interval from validate_gtso.json (`gtbake validate-gtso`) into `gtso`.
void applyValidateGtsoU(const std::filesystem::path& file, GtsoInput* gtso);

}  // namespace gtbake
