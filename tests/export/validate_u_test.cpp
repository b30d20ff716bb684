// export takes u, its scene-level interval and its SE from validate_gtso.json: the SE goes into
// kConeApertureUStdError; a file without u_se carries none.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/output_set.h"
#include "export/export_inputs.h"

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

TEST(ExportValidateU, ShipsTheSceneLevelStandardError) {
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

}  // namespace
}  // namespace gtbake
