#include "fit/fit_set.h"

#include <algorithm>
#include <cmath>
#include <regex>

#include "common/error.h"
#include "common/input_limits.h"
#include "common/output_set.h"

namespace gtbake {

FitInput readFitInput(const std::filesystem::path& file) {
  FitInput in;
  if (!std::filesystem::is_regular_file(file)) throw Error("no such file: " + file.string());
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : ".";
  in.json = readOutputSet(dir, "fit").readVerifiedJson(file.filename().string());
  const std::string where = file.string();
  const nlohmann::json& linear = jsonMember(in.json, "linear", where);
  const nlohmann::json& se = jsonMember(in.json, "linear_se", where);
  for (int i = 0; i < 6; ++i) {
    in.linear[i] = shippedNumber(linear, kCoeffNames[i], where + " linear");
    in.linear_se[i] = shippedNumber(se, kCoeffNames[i], where + " linear_se", true);
  }
  return in;
}

namespace {

// Bounds of a shipped profile table (docs/profiles.md §8): what `gtbake fit` writes fits well
// inside them (32 nodes × the sweep's albedos), and a file cannot make export emit a huge array.
constexpr std::int64_t kMaxTableNodes = 256;
constexpr std::size_t kMaxTableRhos = 16;

// fit.json /profile/table into p when the fit says the table is needed: node count, ascending
// albedos in (0, 1], every row non-decreasing in [0, 1] with G(1) = 1 (the shape the table is
// shipped for). Throws one line otherwise.
void readProfileTable(const nlohmann::json& fit, const std::string& where, ProfileInput* p) {
  if (!fit.contains("profile") || !fit["profile"].is_object() ||
      !fit["profile"].contains("table")) {
    return;
  }
  const std::string at = where + " profile/table";
  const nlohmann::json& t = fit["profile"]["table"];
  if (!jsonMember(t, "needed", at).is_boolean()) throw Error(at + ": 'needed' must be a boolean");
  if (!t["needed"].get<bool>()) return;
  const int nodes = static_cast<int>(jsonInteger(t, "A_nodes", 2, kMaxTableNodes, at));
  const nlohmann::json& rhos = jsonMember(t, "rho", at);
  const nlohmann::json& rows = jsonMember(t, "values", at);
  if (!rhos.is_array() || rhos.empty() || rhos.size() > kMaxTableRhos || !rows.is_array() ||
      rows.size() != rhos.size()) {
    throw Error(at + ": 'rho' must list 1 to " + std::to_string(kMaxTableRhos) +
                " albedos and 'values' one row per albedo");
  }
  for (std::size_t j = 0; j < rhos.size(); ++j) {
    const double rho = rhos[j].is_number() ? rhos[j].get<double>() : NAN;
    if (!(rho > 0.0 && rho <= 1.0) || (j > 0 && !(rho > p->table_rhos.back()))) {
      throw Error(at + ": 'rho' must be ascending albedos in (0, 1]");
    }
    p->table_rhos.push_back(rho);
    if (!rows[j].is_array() || rows[j].size() != static_cast<std::size_t>(nodes)) {
      throw Error(at + ": every row of 'values' must hold A_nodes values");
    }
    for (std::size_t i = 0; i < rows[j].size(); ++i) {
      const double g = rows[j][i].is_number() ? rows[j][i].get<double>() : NAN;
      const bool rises = i == 0 || g >= p->table_values.back();
      if (!(g >= 0.0 && g <= 1.0) || !rises || (i + 1 == rows[j].size() && g != 1.0)) {
        throw Error(at + ": every row must rise in [0, 1] to G(1) = 1");
      }
      p->table_values.push_back(g);
    }
  }
  p->table_nodes = nodes;
  p->table_held_out_rmse = shippedNumber(t, "held_out_by_scene_rmse", at, true);
}

}  // namespace

std::vector<ProfileInput> readProfiles(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::vector<std::string> names;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (e.is_directory() && fs::is_regular_file(e.path() / manifestFileName("fit"))) {
      names.push_back(e.path().filename().string());
    }
  }
  if (ec) throw Error("cannot read the profiles directory " + dir.string() + ": " + ec.message());
  std::sort(names.begin(), names.end());
  static const std::regex kName("[a-z][a-z0-9-]{0,31}");
  std::vector<ProfileInput> out;
  for (const std::string& name : names) {
    const fs::path file = dir / name / "fit.json";
    if (!std::regex_match(name, kName)) {
      throw Error(file.string() + ": a profile's estimator name must be lower-case letters, " +
                  "digits and '-' (at most 32)");
    }
    const FitInput fit = readFitInput(file);
    const std::string where = file.string();
    const nlohmann::json& input = jsonMember(fit.json, "input", where);
    if (!input.contains("estimator") || input["estimator"] != name) {
      throw Error(where + ": not the profile of estimator '" + name +
                  "' (fit.json /input/estimator; rerun `gtbake fit --estimator " + name + "`)");
    }
    const nlohmann::json& errors = jsonMember(fit.json, "errors", where);
    ProfileInput p;
    p.estimator = name;
    p.linear = fit.linear;
    p.rmse_paper = shippedNumber(jsonMember(errors, "shipped", where), "rmse",
                                 where + " errors/shipped", true);
    p.rmse_held_out = shippedNumber(jsonMember(errors, "held_out_by_scene", where), "rmse",
                                    where + " errors/held_out_by_scene", true);
    const nlohmann::json& jk = jsonMember(fit.json, "scene_jackknife", where);
    if (jk.contains("band_max")) {
      p.band_max =
          shippedNumber(jk["band_max"], "value", where + " scene_jackknife/band_max", true);
    }
    p.gate = profileGate(shapeChecks(p.linear), p.rmse_held_out, p.rmse_paper);
    readProfileTable(fit.json, where, &p);
    out.push_back(p);
  }
  return out;
}

}  // namespace gtbake
