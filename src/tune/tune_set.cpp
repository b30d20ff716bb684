#include "tune/tune_set.h"

#include <regex>

#include "common/error.h"
#include "common/input_limits.h"
#include "common/output_set.h"
#include "fit/multibounce_coeffs.h"

namespace gtbake {

namespace {

// tune.json results/<estimator>/<setting> as one TunedSettingInput.
TunedSettingInput tunedSetting(const std::string& estimator, const std::string& setting,
                               const nlohmann::json& r, const std::string& where) {
  TunedSettingInput t;
  t.estimator = estimator;
  t.setting = setting;
  t.default_value = shippedNumber(r, "default", where);
  const nlohmann::json& optimum = jsonMember(r, "optimum", where);
  const nlohmann::json& paper = jsonMember(optimum, "paper", where + " optimum");
  const nlohmann::json& profile = jsonMember(optimum, "profile", where + " optimum");
  t.paper_best = shippedNumber(paper, "value", where + " optimum/paper");
  t.profile_best = shippedNumber(profile, "value", where + " optimum/profile");
  const nlohmann::json& interval = jsonMember(profile, "interval", where + " optimum/profile");
  if (!interval.is_array() || interval.size() != 2 || !interval[0].is_number() ||
      !interval[1].is_number()) {
    throw Error(where + ": optimum/profile/interval must be [low, high]");
  }
  t.profile_low = interval[0].get<double>();
  t.profile_high = interval[1].get<double>();
  const nlohmann::json& bound = jsonMember(profile, "at_bound", where + " optimum/profile");
  if (!bound.is_boolean()) throw Error(where + ": optimum/profile/at_bound must be true or false");
  t.at_bound = bound.get<bool>();
  const nlohmann::json& best = jsonMember(profile, "grid_best", where + " optimum/profile");
  t.grid_value = shippedNumber(best, "value", where + " optimum/profile/grid_best");
  t.rmse_held_out =
      shippedNumber(best, "profile_held_out", where + " optimum/profile/grid_best", true);
  const nlohmann::json& refit = jsonMember(profile, "refit", where + " optimum/profile");
  for (std::size_t i = 0; i < 6; ++i) {
    t.linear[i] = shippedNumber(refit, kCoeffNames[i], where + " optimum/profile/refit");
  }
  return t;
}

}  // namespace

std::vector<TunedSettingInput> readTunedSettings(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) throw Error("no such file: " + file.string());
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : ".";
  const nlohmann::json j = readOutputSet(dir, "tune").readVerifiedJson(file.filename().string());
  const std::string where = file.string();
  const nlohmann::json& results = jsonMember(j, "results", where);
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

}  // namespace gtbake
