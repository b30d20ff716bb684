// `gtbake validate` as a CI job drives it (docs/fit.md §10): the coefficient table against numbers
// chosen here (given = refit + k·SE scene prints diff/SEscene = k), the exit codes (0 consistent,
// 3 outside, 4 too few scenes to judge), --json, the same report from the sweep and from the
// fit's shipped sums, and bad options.
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

constexpr std::array<const char*, 6> kNames = {"a1", "a0", "b1", "b0", "c1", "c0"};

std::string printed(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

// A small sweep of the seven classic scenes and its fit, made once (luts/ does not commit the
// sweep's per-view images, docs/reproducibility.md).
class Validate : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("validate-cli");
    const std::string scenes = (fs::path(GTBAKE_SOURCE_DIR) / "data" / "scenes").string();
    const RunResult swept =
        runGtbake("sweep --quiet --scenes " + scenes + " --out " + sweep().string() +
                  " --res 32x32 --spp 32 --specular-roughness none --gbuffer-radius none");
    ASSERT_EQ(swept.exit_code, 0) << swept.err;
    const RunResult fitted =
        runGtbake("fit --quiet --sweep " + sweep().string() + " --out " + fitJson().string());
    ASSERT_EQ(fitted.exit_code, 0) << fitted.err;
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path sweep() { return dir_->path() / "sweep"; }
  static fs::path fitDir() { return dir_->path() / "fit"; }
  static fs::path fitJson() { return fitDir() / "fit.json"; }
  static json fit() { return json::parse(readBytes(fitJson())); }
  // The refit's constants moved by `offset` (scene SEs), as --coeffs text.
  static std::string refitPlus(const std::array<double, 6>& offset) {
    const json f = fit();
    std::string coeffs;
    for (std::size_t i = 0; i < kNames.size(); ++i) {
      const double refit = f["linear"][kNames[i]].get<double>();
      const double se = f["scene_jackknife"]["se"][kNames[i]].get<double>();
      coeffs += (i ? "," : "") + printed("%.17g", refit + offset[i] * se);
    }
    return coeffs;
  }
  static TempDir* dir_;
};
TempDir* Validate::dir_ = nullptr;

TEST_F(Validate, DiffOverSceneSeColumnIsTheGivenOffset) {
  // Distinct offsets, none near a rounding boundary of %.1f, so a swapped or misnamed column fails.
  const std::array<double, 6> k = {2.0, -3.0, 0.5, 1.0, -1.5, 4.0};
  const RunResult run =
      runGtbake("validate --quiet --sweep " + sweep().string() + " --coeffs " + refitPlus(k));
  ASSERT_NE(run.exit_code, 1) << run.err;
  const json f = fit();
  int rows = 0;
  std::istringstream lines(run.out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::string name, given, refit, se, diff;
    if (!(fields >> name >> given >> refit >> se >> diff)) continue;
    for (std::size_t i = 0; i < kNames.size(); ++i) {
      if (name != kNames[i]) continue;
      EXPECT_EQ(diff, printed("%.1f", k[i])) << line;
      EXPECT_EQ(refit, printed("%.4f", f["linear"][kNames[i]].get<double>())) << line;
      EXPECT_EQ(se, printed("%.4f", f["scene_jackknife"]["se"][kNames[i]].get<double>())) << line;
      ++rows;
    }
  }
  EXPECT_EQ(rows, 6) << run.out;
}

// Seven 32 x 32 scenes detect only differences of ~0.1: the paper's constants cannot be judged
// (exit 4); constants far off are still found outside (exit 3); with a tolerance of 0.2 the refit
// itself is consistent (exit 0). The JSON says the same, and the fit's sums give the same report
// as the sweep's images.
TEST_F(Validate, ExitCodesAndJsonFollowTheVerdict) {
  const fs::path from_sweep = dir_->path() / "from_sweep.json";
  const fs::path from_luts = dir_->path() / "from_luts.json";
  const RunResult paper =
      runGtbake("validate --quiet --sweep " + sweep().string() + " --json " + from_sweep.string());
  EXPECT_EQ(paper.exit_code, 4) << paper.out << paper.err;
  EXPECT_NE(paper.out.find("verdict: too few scenes to judge"), std::string::npos) << paper.out;
  const RunResult luts =
      runGtbake("validate --quiet --luts " + fitDir().string() + " --json " + from_luts.string());
  EXPECT_EQ(luts.exit_code, 4) << luts.err;
  json a = json::parse(readBytes(from_sweep)), b = json::parse(readBytes(from_luts));
  EXPECT_EQ(a["verdict"]["verdict"], "too few scenes to judge");
  EXPECT_EQ(a["verdict"]["ranges"].size(), 3u);
  a.erase("data");
  b.erase("data");
  EXPECT_EQ(a, b);

  const RunResult far = runGtbake("validate --quiet --luts " + fitDir().string() + " --coeffs " +
                                  refitPlus({0, 0, 0, 0, 0, 12.0}));
  EXPECT_EQ(far.exit_code, 3) << far.out << far.err;
  EXPECT_NE(far.out.find("verdict: outside"), std::string::npos) << far.out;

  const RunResult same = runGtbake("validate --quiet --luts " + fitDir().string() + " --coeffs " +
                                   refitPlus({0, 0, 0, 0, 0, 0}) + " --fail-above 0.2");
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  EXPECT_NE(same.out.find("verdict: consistent"), std::string::npos) << same.out;
}

TEST_F(Validate, ThreeScenesAreTooFewToJudge) {
  const fs::path scenes = fs::path(GTBAKE_SOURCE_DIR) / "data" / "scenes";
  const fs::path three = dir_->path() / "three";
  const RunResult swept = runGtbake(
      "sweep --quiet --scenes " + (scenes / "cavity.gltf").string() + " " +
      (scenes / "corner.gltf").string() + " " + (scenes / "terrain.gltf").string() + " --out " +
      three.string() + " --res 32x32 --spp 32 --specular-roughness none --gbuffer-radius none");
  ASSERT_EQ(swept.exit_code, 0) << swept.err;
  const RunResult run = runGtbake("validate --quiet --sweep " + three.string());
  EXPECT_EQ(run.exit_code, 4) << run.out << run.err;
  EXPECT_NE(run.out.find("verdict: too few scenes to judge"), std::string::npos) << run.out;
}

TEST_F(Validate, BadOptionsAreOneLineErrors) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"validate --quiet --sweep " + sweep().string() + " --luts " + fitDir().string(),
       "either --sweep DIR"},
      {"validate --quiet", "either --sweep DIR"},
      {"validate --quiet --luts " + fitDir().string() + " --fail-above 0", "--fail-above"},
      {"validate --quiet --luts " + fitDir().string() + " --weighting view", "needs --sweep"},
      {"validate --quiet --luts " + fitDir().string() + " --json " +
           (fitDir() / "validate_data.json").string(),
       "--json"},
      {"validate --quiet --luts " + sweep().string(), "fit.manifest.json"},
  };
  for (const auto& [arguments, expected] : cases) {
    const RunResult run = runGtbake(arguments);
    EXPECT_EQ(run.exit_code, 1) << arguments;
    EXPECT_NE(run.err.find(expected), std::string::npos) << arguments << ": " << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  }
}

}  // namespace
}  // namespace gtbake::test
