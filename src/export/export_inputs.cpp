#include "export/export_inputs.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <regex>

#include "common/atomic_file.h"
#include "common/checked_math.h"
#include "common/error.h"
#include "common/input_limits.h"
#include "common/output_set.h"
#include "common/text_escape.h"
#include "runtime/gtso_runtime.h"

namespace gtbake {
namespace {

constexpr const char* kCoeffNames[6] = {"a1", "a0", "b1", "b0", "c1", "c0"};
constexpr const char* kAxisNames[4] = {"x", "y", "z", "w"};
constexpr int kMaxAxisTexels = 4096;  // far beyond any table gtbake bakes; rejects garbage dims

// A JSON file of an output set, verified against the set's manifest before it is parsed.
nlohmann::json parseJson(const OutputManifest& set, const std::string& name) {
  const std::filesystem::path path = set.dir / name;
  try {
    return parseJsonText(set.readVerified(name), path.string());
  } catch (const Error& e) {
    const std::string what = e.what();
    if (what.find("malformed JSON") == std::string::npos) throw;
    throw Error(path.string() + ": not valid JSON (" + what + ")");
  }
}

const nlohmann::json& member(const nlohmann::json& j, const std::string& key,
                             const std::string& where) {
  if (!j.is_object() || !j.contains(key)) throw Error(where + ": missing key \"" + key + "\"");
  return j.at(key);
}

// A constant the generated code ships, or a standard error of one: finite and at most
// kMaxShippedMagnitude in size, so it prints as a finite float literal (docs/limits.md §Values).
double shippedNumber(const nlohmann::json& j, const std::string& key, const std::string& where,
                     bool non_negative = false) {
  return jsonNumber(j, key.c_str(), non_negative ? 0.0 : -kMaxShippedMagnitude,
                    kMaxShippedMagnitude, where);
}

GtsoTable readTable(const OutputManifest& set, const nlohmann::json& tables, const std::string& key,
                    int rank) {
  const std::filesystem::path& dir = set.dir;
  const std::string where = (dir / "gtso.json").string() + " tables." + key;
  const nlohmann::json& t = member(tables, key, (dir / "gtso.json").string() + " tables");
  GtsoTable table;
  table.meta = t;
  const nlohmann::json& file = member(t, "file", where);
  if (!file.is_string()) throw Error(where + ": \"file\" must be a string");
  table.file = file.get<std::string>();
  // The name reaches the generated code's comments: only a plain file name (docs/limits.md
  // §Names in outputs).
  if (fileSlug(table.file) != table.file) {
    throw Error(where + ": \"file\" must be a plain file name of [A-Za-z0-9_.-], got " +
                file.dump());
  }
  const nlohmann::json& dims = member(t, "dims", where);
  if (!dims.is_array() || static_cast<int>(dims.size()) != rank) {
    throw Error(where + ": \"dims\" must list " + std::to_string(rank) + " sizes");
  }
  for (const auto& d : dims) {
    if (!d.is_number_integer() || d.get<std::int64_t>() < 2 ||
        d.get<std::int64_t>() > kMaxAxisTexels) {
      throw Error(where + ": every entry of \"dims\" must be an integer in [2, 4096]");
    }
    table.dims.push_back(d.get<int>());
  }
  if (table.dims[0] % 4 != 0 || table.dims[1] % 4 != 0) {
    throw Error(where + ": x and y sizes must be multiples of 4 for BC4 blocks");
  }
  const nlohmann::json& axes = member(t, "axes", where);
  if (!axes.is_array() || static_cast<int>(axes.size()) != rank) {
    throw Error(where + ": \"axes\" must list " + std::to_string(rank) + " axes");
  }
  const GtsoAxisInfo* const* expected = rank == 3 ? kGtso3DAxisInfo : kGtso4DAxisInfo;
  for (int i = 0; i < rank; ++i) {
    const nlohmann::json& a = axes[i];
    const nlohmann::json& name = member(a, "axis", where + ".axes");
    const nlohmann::json& quantity = member(a, "quantity", where + ".axes");
    if (!name.is_string() || name.get<std::string>() != kAxisNames[i]) {
      throw Error(where + ": axis " + std::to_string(i) + " must be named \"" + kAxisNames[i] +
                  "\"");
    }
    if (!quantity.is_string() || quantity.get<std::string>() != expected[i]->quantity) {
      throw Error(where + ": axis " + kAxisNames[i] + " has quantity " + quantity.dump() +
                  ", the runtime lookup expects \"" + expected[i]->quantity + "\"");
    }
    table.axes.push_back({kAxisNames[i], quantity.get<std::string>()});
  }
  table.volume = {table.dims[0], table.dims[1],
                  rank == 4 ? table.dims[2] * table.dims[3] : table.dims[2]};
  const std::size_t count =
      checkedMul(checkedMul(static_cast<std::uint64_t>(table.volume[0]), table.volume[1], where),
                 static_cast<std::uint64_t>(table.volume[2]), where);
  checkLimit(kMaxInputBytes, checkedMul(count, sizeof(float), where), where);
  fileInsideDirectory(dir, table.file, where);
  const std::string bytes = set.readVerified(table.file);
  if (bytes.size() != count * sizeof(float)) {
    throw Error((dir / table.file).string() + ": " + std::to_string(bytes.size()) +
                " bytes, expected " + std::to_string(count * sizeof(float)) +
                " (float32 little-endian, dims from gtso.json)");
  }
  table.values.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t bits = 0;
    for (int b = 0; b < 4; ++b) {
      bits |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[4 * i + b])) << (8 * b);
    }
    std::memcpy(&table.values[i], &bits, sizeof(float));
    if (!std::isfinite(table.values[i])) {
      throw Error((dir / table.file).string() + ": texel " + std::to_string(i) +
                  " is not a finite number");
    }
  }
  return table;
}

// The axis constants the tables were baked with must be the runtime's.
void checkAxisConstants(const nlohmann::json& j, const std::string& where) {
  const nlohmann::json& c = member(j, "axis_constants", where);
  for (const auto& [key, macro, value] : kGtsoAxisConstants) {
    if (shippedNumber(c, key, where + " axis_constants") != value) {
      throw Error(where + ": axis_constants." + key +
                  " differs from this gtbake's runtime lookup (" + std::to_string(value) +
                  "); re-run `gtbake gtso`");
    }
  }
}

}  // namespace

GtsoInput readGtsoInput(const std::filesystem::path& dir) {
  if (!std::filesystem::is_directory(dir)) {
    throw Error("--gtso " + dir.string() + ": not a directory (run `gtbake gtso --out DIR`)");
  }
  GtsoInput in;
  const OutputManifest set = readOutputSet(dir, "gtso");
  in.json = parseJson(set, "gtso.json");
  in.json_dir = dir;
  const std::string where = (dir / "gtso.json").string();
  checkAxisConstants(in.json, where);
  const nlohmann::json& tables = member(in.json, "tables", where);
  in.table3d = readTable(set, tables, "3d", 3);
  in.table4d = readTable(set, tables, "4d", 4);
  const nlohmann::json& cone = member(in.json, "cone", where);
  in.u = shippedNumber(cone, "u", where + " cone");
  in.u_se = shippedNumber(cone, "u_se", where + " cone", true);
  if (!(in.u > 0.0 && in.u < 1.0)) throw Error(where + ": cone.u must lie in (0, 1)");
  const nlohmann::json& closedForm = member(in.json, "closed_form", where);
  const nlohmann::json& coeffs = member(closedForm, "coefficients", where + " closed_form");
  if (!coeffs.is_array() || coeffs.size() != static_cast<std::size_t>(kGtsoS3ClosedFormCoeffs)) {
    throw Error(where + ": closed_form.coefficients must list " +
                std::to_string(kGtsoS3ClosedFormCoeffs) +
                " numbers (the form of this gtbake's runtime); re-run `gtbake gtso`");
  }
  for (const auto& c : coeffs) {
    if (!c.is_number() || !(std::abs(c.get<double>()) <= kMaxShippedMagnitude)) {
      throw Error(where +
                  ": closed_form.coefficients must be finite numbers of magnitude at most " +
                  std::to_string(static_cast<int>(kMaxShippedMagnitude)));
    }
    in.s3_closed_form.push_back(c.get<double>());
  }
  return in;
}

FitInput readFitInput(const std::filesystem::path& file) {
  FitInput in;
  if (!std::filesystem::is_regular_file(file)) throw Error("no such file: " + file.string());
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : ".";
  in.json = parseJson(readOutputSet(dir, "fit"), file.filename().string());
  const std::string where = file.string();
  const nlohmann::json& linear = member(in.json, "linear", where);
  const nlohmann::json& se = member(in.json, "linear_se", where);
  for (int i = 0; i < 6; ++i) {
    in.linear[i] = shippedNumber(linear, kCoeffNames[i], where + " linear");
    in.linear_se[i] = shippedNumber(se, kCoeffNames[i], where + " linear_se", true);
  }
  return in;
}

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
    const nlohmann::json& input = member(fit.json, "input", where);
    if (!input.contains("estimator") || input["estimator"] != name) {
      throw Error(where + ": not the profile of estimator '" + name +
                  "' (fit.json /input/estimator; rerun `gtbake fit --estimator " + name + "`)");
    }
    const nlohmann::json& errors = member(fit.json, "errors", where);
    ProfileInput p;
    p.estimator = name;
    p.linear = fit.linear;
    p.rmse_paper =
        shippedNumber(member(errors, "shipped", where), "rmse", where + " errors/shipped", true);
    p.rmse_held_out = shippedNumber(member(errors, "held_out_by_scene", where), "rmse",
                                    where + " errors/held_out_by_scene", true);
    const nlohmann::json& jk = member(fit.json, "scene_jackknife", where);
    if (jk.contains("band_max")) {
      p.band_max =
          shippedNumber(jk["band_max"], "value", where + " scene_jackknife/band_max", true);
    }
    out.push_back(p);
  }
  return out;
}

namespace {

// tune.json results/<estimator>/<setting> as one TunedSettingInput.
TunedSettingInput tunedSetting(const std::string& estimator, const std::string& setting,
                               const nlohmann::json& r, const std::string& where) {
  TunedSettingInput t;
  t.estimator = estimator;
  t.setting = setting;
  t.default_value = shippedNumber(r, "default", where);
  const nlohmann::json& optimum = member(r, "optimum", where);
  const nlohmann::json& paper = member(optimum, "paper", where + " optimum");
  const nlohmann::json& profile = member(optimum, "profile", where + " optimum");
  t.paper_best = shippedNumber(paper, "value", where + " optimum/paper");
  t.profile_best = shippedNumber(profile, "value", where + " optimum/profile");
  const nlohmann::json& interval = member(profile, "interval", where + " optimum/profile");
  if (!interval.is_array() || interval.size() != 2 || !interval[0].is_number() ||
      !interval[1].is_number()) {
    throw Error(where + ": optimum/profile/interval must be [low, high]");
  }
  t.profile_low = interval[0].get<double>();
  t.profile_high = interval[1].get<double>();
  const nlohmann::json& bound = member(profile, "at_bound", where + " optimum/profile");
  if (!bound.is_boolean()) throw Error(where + ": optimum/profile/at_bound must be true or false");
  t.at_bound = bound.get<bool>();
  const nlohmann::json& best = member(profile, "grid_best", where + " optimum/profile");
  t.grid_value = shippedNumber(best, "value", where + " optimum/profile/grid_best");
  t.rmse_held_out =
      shippedNumber(best, "profile_held_out", where + " optimum/profile/grid_best", true);
  const nlohmann::json& refit = member(profile, "refit", where + " optimum/profile");
  for (std::size_t i = 0; i < 6; ++i) {
    t.linear[i] = shippedNumber(refit, kCoeffNames[i], where + " optimum/profile/refit");
  }
  return t;
}

}  // namespace

std::vector<TunedSettingInput> readTunedSettings(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) throw Error("no such file: " + file.string());
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : ".";
  const nlohmann::json j = parseJson(readOutputSet(dir, "tune"), file.filename().string());
  const std::string where = file.string();
  const nlohmann::json& results = member(j, "results", where);
  if (!results.is_object()) throw Error(where + ": results must be an object");
  static const std::regex kEstimator("[a-z][a-z0-9-]{0,31}");
  static const std::regex kSetting("[a-z][a-z_]{0,31}");
  std::vector<TunedSettingInput> out;
  for (const auto& [estimator, settings] : results.items()) {
    if (!std::regex_match(estimator, kEstimator) || !settings.is_object()) {
      throw Error(where + ": results/" + estimator.substr(0, 40) +
                  " is not an estimator's settings");
    }
    for (const auto& [setting, r] : settings.items()) {
      if (!std::regex_match(setting, kSetting)) {
        throw Error(where + ": results/" + estimator + "/" + setting.substr(0, 40) +
                    " is not a setting name");
      }
      out.push_back(
          tunedSetting(estimator, setting, r, where + " results/" + estimator + "/" + setting));
    }
  }
  return out;
}

void applyValidateGtsoU(const std::filesystem::path& file, GtsoInput* gtso) {
  if (!std::filesystem::is_regular_file(file)) throw Error("no such file: " + file.string());
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : ".";
  const nlohmann::json j = parseJson(readOutputSet(dir, "validate_gtso"), file.filename().string());
  const std::string where = file.string();
  const double u = shippedNumber(j, "u", where);
  const nlohmann::json& interval = member(j, "u_interval", where);
  if (!interval.is_array() || interval.size() != 2 || !interval[0].is_number() ||
      !interval[1].is_number()) {
    throw Error(where + ": u_interval must be [low, high]");
  }
  const double low = interval[0].get<double>();
  const double high = interval[1].get<double>();
  // validate-gtso clamps the interval's upper end to u = 1 (few scenes give a wide interval).
  if (!(u > 0.0 && u < 1.0 && low > 0.0 && low <= u && u <= high && high <= 1.0)) {
    throw Error(where + ": u must lie in (0, 1) inside u_interval, and u_interval in (0, 1]");
  }
  gtso->u = u;
  // The scene-level SE (delete-one-scene jackknife, validate_gtso.json u_scene_interval); files
  // without it carry no standard error.
  gtso->u_se = j.contains("u_se") ? shippedNumber(j, "u_se", where, true) : 0.0;
  gtso->u_low = low;
  gtso->u_high = high;
  gtso->validate_gtso = j;
}

}  // namespace gtbake
