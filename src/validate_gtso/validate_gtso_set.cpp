#include "validate_gtso/validate_gtso_set.h"

#include "common/error.h"
#include "common/input_limits.h"
#include "common/output_set.h"

namespace gtbake {

ValidateGtsoU readValidateGtsoU(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) throw Error("no such file: " + file.string());
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : ".";
  const nlohmann::json j =
      readOutputSet(dir, "validate_gtso").readVerifiedJson(file.filename().string());
  const std::string where = file.string();
  const double u = shippedNumber(j, "u", where);
  const nlohmann::json& interval = jsonMember(j, "u_interval", where);
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
  ValidateGtsoU v;
  v.u = u;
  // The scene-level SE (delete-one-scene jackknife, validate_gtso.json u_scene_interval); files
  // without it carry no standard error.
  v.u_se = j.contains("u_se") ? shippedNumber(j, "u_se", where, true) : 0.0;
  v.low = low;
  v.high = high;
  v.json = j;
  return v;
}

void applyValidateGtsoU(const std::filesystem::path& file, GtsoInput* gtso) {
  const ValidateGtsoU v = readValidateGtsoU(file);
  gtso->u = v.u;
  gtso->u_se = v.u_se;
  gtso->u_low = v.low;
  gtso->u_high = v.high;
  gtso->validate_gtso = v.json;
}

}  // namespace gtbake
