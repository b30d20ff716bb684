// The verdict as a fresh clone gets it (docs/fit.md §5, §10): from luts/fit/validate_data.json, the
// refit is consistent in every range with power to spare, the paper's constants get the verdict
// fit.json records, and known mid-A errors of 0.02 and 0.03 in G are found outside in [0.3, 0.7).
#include <gtest/gtest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "common/input_limits.h"
#include "fit/validate_output.h"
#include "fit/validate_report.h"

namespace gtbake {
namespace {

std::filesystem::path luts() {
  const char* env = std::getenv("GTBAKE_LUTS_DIR");
  return env != nullptr ? std::filesystem::path(env)
                        : std::filesystem::path(GTBAKE_SOURCE_DIR) / "luts";
}

TEST(LutsVerdict, RefitIsConsistentWithPowerInEveryRange) {
  const ValidateData d = readValidateData(luts() / "fit");
  const CurveVerdict v = validateReport(d, d.refit).verdict;
  EXPECT_EQ(v.verdict, Verdict::kConsistent) << v.headline;
  for (const RangeScore& r : v.ranges) EXPECT_LT(r.detectable.value, kUsefulPower) << r.text;
}

TEST(LutsVerdict, PaperVerdictIsWhatFitJsonRecords) {
  const ValidateData d = readValidateData(luts() / "fit");
  const nlohmann::json recorded = readJsonFile(luts() / "fit" / "fit.json")["shipped"]["verdict"];
  const nlohmann::json now =
      nlohmann::json::parse(curveVerdictJson(validateReport(d, kPaperCoeffs).verdict).dump());
  EXPECT_EQ(now, recorded);
}

TEST(LutsVerdict, KnownMidRangeErrorsAreOutsideInTheirRange) {
  const ValidateData d = readValidateData(luts() / "fit");
  for (double peak : {0.02, 0.03}) {
    MultiBounceCoeffs k = d.refit;  // ΔG = 4·peak·A(1 − A): peak at A = 0.5, 0 at A = 0 and 1
    k[3] += 4.0 * peak;
    k[5] += 4.0 * peak;
    const CurveVerdict v = validateReport(d, k).verdict;
    EXPECT_EQ(v.verdict, Verdict::kOutside) << v.headline;
    EXPECT_EQ(v.ranges[1].verdict, Verdict::kOutside) << v.ranges[1].text;
    EXPECT_NEAR(v.ranges[1].max_difference.value, peak, 1e-12);
  }
}

}  // namespace
}  // namespace gtbake
