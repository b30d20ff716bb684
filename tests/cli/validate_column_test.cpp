// validate's coefficient table, checked against numbers chosen here: given = refit + k·SE must
// print diff/SE = k, and the refit and SE columns must be fit.json's (same sweep, same fit).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_harness.h"

namespace gtbake::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string printed(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

TEST(Validate, DiffOverSeColumnIsTheGivenOffsetInStandardErrors) {
  // A small sweep of the seven classic scenes and its fit (luts/ does not commit the sweep's
  // per-view images, docs/reproducibility.md).
  const TempDir dir("validate-column");
  const fs::path sweep = dir.path() / "sweep";
  const std::string scenes = (fs::path(GTBAKE_SOURCE_DIR) / "data" / "scenes").string();
  const RunResult swept =
      runGtbake("sweep --quiet --scenes " + scenes + " --out " + sweep.string() +
                " --res 32x32 --spp 32 --specular-roughness none "
                "--gbuffer-radius none");
  ASSERT_EQ(swept.exit_code, 0) << swept.err;
  const fs::path fit_path = dir.path() / "fit" / "fit.json";
  const RunResult fitted =
      runGtbake("fit --sweep " + sweep.string() + " --out " + fit_path.string());
  ASSERT_EQ(fitted.exit_code, 0) << fitted.err;
  const json fit = json::parse(readBytes(fit_path));
  const std::array<const char*, 6> names = {"a1", "a0", "b1", "b0", "c1", "c0"};
  // Distinct offsets, none near a rounding boundary of %.1f, so a swapped or misnamed column fails.
  const std::array<double, 6> k = {2.0, -3.0, 0.5, 1.0, -1.5, 4.0};
  std::string coeffs;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const double refit = fit["linear"][names[i]].get<double>();
    const double se = fit["linear_se"][names[i]].get<double>();
    coeffs += (i ? "," : "") + printed("%.17g", refit + k[i] * se);
  }
  const RunResult run =
      runGtbake("validate --quiet --sweep " + sweep.string() + " --coeffs " + coeffs);
  ASSERT_EQ(run.exit_code, 0) << run.err;

  int rows = 0;
  std::istringstream lines(run.out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::string name, given, refit, se, diff;
    if (!(fields >> name >> given >> refit >> se >> diff)) continue;
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (name != names[i]) continue;
      EXPECT_EQ(diff, printed("%.1f", k[i])) << line;
      EXPECT_EQ(refit, printed("%.4f", fit["linear"][names[i]].get<double>())) << line;
      EXPECT_EQ(se, printed("%.5f", fit["linear_se"][names[i]].get<double>())) << line;
      ++rows;
    }
  }
  EXPECT_EQ(rows, 6) << run.out;
}

}  // namespace
}  // namespace gtbake::test
