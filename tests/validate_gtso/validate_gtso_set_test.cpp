// validate-gtso's reader (validate_gtso/validate_gtso_set.h) gives export u, its scene-level
// interval and its SE from validate_gtso.json: the SE goes into kConeApertureUStdError; a file
// without u_se carries none.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/output_set.h"
#include "validate_gtso/validate_gtso_set.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

fs::path writeValidateGtso(const std::string& name, const nlohmann::json& j) {
  const fs::path dir = fs::temp_directory_path() / ("gtbake_validate_u_" + name);
  fs::remove_all(dir);
  OutputSet set(dir, "validate_gtso");
  set.add("validate_gtso.json", j.dump());
  set.commit();
  return dir / "validate_gtso.json";
}

TEST(ValidateGtsoSetU, ShipsTheSceneLevelStandardError) {
  nlohmann::json j = {{"u", 0.004}, {"u_interval", {0.0005, 0.03}}, {"u_se", 0.0033}};
  GtsoInput gtso;
  applyValidateGtsoU(writeValidateGtso("se", j), &gtso);
  EXPECT_EQ(gtso.u, 0.004);
  EXPECT_EQ(gtso.u_se, 0.0033);
  EXPECT_EQ(gtso.u_low, 0.0005);
  EXPECT_EQ(gtso.u_high, 0.03);
  j.erase("u_se");
  GtsoInput old;
  applyValidateGtsoU(writeValidateGtso("no_se", j), &old);
  EXPECT_EQ(old.u_se, 0.0);
  fs::remove_all(fs::temp_directory_path() / "gtbake_validate_u_se");
  fs::remove_all(fs::temp_directory_path() / "gtbake_validate_u_no_se");
}

// With few scenes validate-gtso's interval reaches its clamp at u = 1 (u_scene_interval.cpp): such
// a file is shipped, and an interval beyond 1 or not around u is refused.
TEST(ValidateGtsoSetU, AnIntervalClampedAtOneIsShippedAndBadOnesAreRefused) {
  GtsoInput gtso;
  applyValidateGtsoU(
      writeValidateGtso("clamped", {{"u", 0.3}, {"u_interval", {0.01, 1.0}}, {"u_se", 0.2}}),
      &gtso);
  EXPECT_EQ(gtso.u_high, 1.0);
  for (const nlohmann::json& interval : {nlohmann::json{0.01, 1.5}, nlohmann::json{0.4, 0.5}}) {
    try {
      applyValidateGtsoU(writeValidateGtso("bad", {{"u", 0.3}, {"u_interval", interval}}), &gtso);
      ADD_FAILURE() << "accepted u_interval " << interval.dump();
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("u_interval"), std::string::npos) << e.what();
    }
  }
  fs::remove_all(fs::temp_directory_path() / "gtbake_validate_u_clamped");
  fs::remove_all(fs::temp_directory_path() / "gtbake_validate_u_bad");
}

}  // namespace
}  // namespace gtbake
