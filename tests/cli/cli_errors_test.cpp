// Bad input through the real binary: one line on stderr, a non-zero exit, nothing left behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "cli_harness.h"
#include "common/atomic_file.h"

namespace gtbake::test {
namespace {

namespace fs = std::filesystem;

size_t countLines(const std::string& text) {
  return static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
}

bool isEmptyOrMissing(const fs::path& dir) {
  return !fs::exists(dir) || fs::is_empty(dir);
}

struct BadInvocation {
  std::string name;
  std::string arguments;  // "{out}" is replaced by a fresh output directory
};

// gtest prints a failing parameter with this instead of its raw bytes.
void PrintTo(const BadInvocation& invocation, std::ostream* os) {
  *os << invocation.name << ": gtbake " << invocation.arguments;
}

std::vector<BadInvocation> badInvocations() {
  const std::string scenes = std::string(GTBAKE_SOURCE_DIR) + "/data/scenes/cavity.gltf";
  return {
      {"no_subcommand", ""},
      {"unknown_subcommand", "bake"},
      {"sweep_missing_file", "sweep --scenes /nonexistent/scene.gltf --out {out}"},
      {"sweep_bad_res_text", "sweep --scenes " + scenes + " --out {out} --res 12by12"},
      {"sweep_bad_res_zero", "sweep --scenes " + scenes + " --out {out} --res 0x16"},
      {"sweep_bad_spp_text", "sweep --scenes " + scenes + " --out {out} --spp many"},
      {"sweep_bad_spp_zero", "sweep --scenes " + scenes + " --out {out} --spp 0"},
      {"sweep_bad_bounces", "sweep --scenes " + scenes + " --out {out} --bounces -1"},
      {"sweep_bad_radius", "sweep --scenes " + scenes + " --out {out} --radius -2"},
      {"sweep_bad_transfer", "sweep --scenes " + scenes + " --out {out} --transfer maybe"},
      {"fit_missing_sweep", "fit --sweep /nonexistent --out {out}/fit.json"},
      {"lighting_missing_sweep", "lighting --sweep /nonexistent --env uniform --out {out}"},
      {"lighting_unknown_class", "lighting --sweep /nonexistent --env dusk --out {out}"},
      {"lighting_not_exr", "lighting --sweep /nonexistent --env " + scenes + " --out {out}"},
      {"validate_coeffs_count", "validate --sweep /nonexistent --coeffs 1,2,3"},
      {"validate_coeffs_text", "validate --sweep /nonexistent --coeffs 1,2,3,4,5,x"},
      {"gtso_bad_size", "gtso --out {out} --size 1"},
      {"encode_bad_4d_layout", "encode --gtso /nonexistent --out {out} --4d-layout tiles"},
      {"all_bad_4d_layout", "all --out {out} --4d-layout tiles"},
      {"report_missing_luts", "report --luts /nonexistent --out {out}"},
      {"export_missing_fit", "export --fit /nonexistent/fit.json --gtso /nonexistent --out {out}"},
      {"tune_missing_sweep", "tune --sweep /nonexistent --out {out}"},
      {"gbuffer_missing_sweep", "gbuffer --sweep /nonexistent --out {out}"},
      {"screen_ao_import_builtin_name",
       "screen-ao --sweep /nonexistent --out {out} --import hbao=/nonexistent"},
      {"screen_ao_import_no_dir", "screen-ao --sweep /nonexistent --out {out} --import mine"},
      {"screen_ao_import_bad_radius",
       "screen-ao --sweep /nonexistent --out {out} --import mine=/nonexistent:radius=-1"},
      {"fit_bad_estimator_name", "fit --sweep /nonexistent --out {out}/fit.json --estimator A.B"},
      {"tune_unknown_estimator", "tune --sweep /nonexistent --out {out} --estimators hbao"},
      {"tune_unknown_key", "tune --sweep /nonexistent --out {out} --grid gtao-runtime.steps=2,4"},
      {"tune_grid_without_default",
       "tune --sweep /nonexistent --out {out} --grid gtao-runtime.radius=0.5,2"},
      {"tune_grid_one_value",
       "tune --sweep /nonexistent --out {out} --grid bitmask-cosine.thickness=0.5"},
      {"tune_grid_not_finite",
       "tune --sweep /nonexistent --out {out} --grid gtao-runtime.intensity=1,nan"},
      {"tune_grid_out_of_range",
       "tune --sweep /nonexistent --out {out} --grid gtao-runtime.thin_compensation=0,20"},
  };
}

class CliBadInput : public ::testing::TestWithParam<BadInvocation> {};

TEST_P(CliBadInput, OneLineErrorNonZeroExitNoOutput) {
  const TempDir dir("cli-" + GetParam().name);
  const fs::path out = dir.path() / "out";
  std::string arguments = GetParam().arguments;
  for (size_t at; (at = arguments.find("{out}")) != std::string::npos;) {
    arguments.replace(at, 5, out.string());
  }
  const RunResult result = runGtbake(arguments + " --quiet");
  EXPECT_NE(result.exit_code, 0) << arguments;
  EXPECT_EQ(countLines(result.err), 1u) << result.err;
  EXPECT_EQ(result.err.rfind("gtbake: error: ", 0), 0u) << result.err;
  EXPECT_TRUE(isEmptyOrMissing(out)) << "output left behind by: " << arguments;
}

INSTANTIATE_TEST_SUITE_P(All, CliBadInput, ::testing::ValuesIn(badInvocations()),
                         [](const auto& info) { return info.param.name; });

// An --out directory in the flat layout of an older gtbake is refused in one line before anything
// is written, never mixed with the layout by stage (docs/reproducibility.md "Layout").
TEST(Cli, AllRefusesOlderFlatLayout) {
  const TempDir dir("cli-flat-layout");
  const fs::path out = dir.path() / "old";
  fs::create_directories(out);
  writeFileAtomically(out / "sweep.json", "{}\n");
  writeFileAtomically(out / "notes.txt", "mine\n");
  const RunResult result = runGtbake("all --quiet --out " + out.string());
  EXPECT_NE(result.exit_code, 0);
  EXPECT_EQ(countLines(result.err), 1u) << result.err;
  EXPECT_NE(result.err.find("flat layout of an older gtbake (sweep.json at its top)"),
            std::string::npos)
      << result.err;
  std::vector<std::string> entries;
  for (const auto& e : fs::directory_iterator(out)) entries.push_back(e.path().filename().string());
  std::sort(entries.begin(), entries.end());
  EXPECT_EQ(entries, (std::vector<std::string>{"notes.txt", "sweep.json"}));
  // The fit report an older run left in a checkout whose tracked files moved to the new layout.
  const fs::path left = dir.path() / "left";
  fs::create_directories(left / "report");
  writeFileAtomically(left / "report" / "index.html", "<html></html>\n");
  const RunResult again = runGtbake("all --quiet --out " + left.string());
  EXPECT_NE(again.exit_code, 0);
  EXPECT_NE(again.err.find("(report/index.html at its top)"), std::string::npos) << again.err;
}

TEST(Cli, HelpAndVersionExitZero) {
  EXPECT_EQ(runGtbake("--help").exit_code, 0);
  const RunResult version = runGtbake("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_FALSE(version.out.empty());
}

TEST(Cli, ScenesReproduceCommittedData) {
  const TempDir dir("cli-scenes");
  const RunResult result = runGtbake("scenes --quiet --classic --out " + dir.path().string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const fs::path committed = fs::path(GTBAKE_SOURCE_DIR) / "data" / "scenes";
  size_t compared = 0;
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    const fs::path other = committed / entry.path().filename();
    ASSERT_TRUE(fs::exists(other)) << other << " is not committed";
    EXPECT_EQ(readBytes(entry.path()), readBytes(other)) << other << " differs";
    ++compared;
  }
  EXPECT_EQ(compared, 15u);  // seven scenes, .gltf + .bin each, and scenes.manifest.json
}

// A run killed mid-way must not damage the good file that was already there.
TEST(Cli, KilledRunLeavesEarlierOutputIntact) {
  const TempDir dir("cli-kill");
  const std::string out = dir.path().string();
  const std::string scene = std::string(GTBAKE_SOURCE_DIR) + "/data/scenes/cavity.gltf";
  const std::string sweep = "sweep --quiet --threads 1 --scenes " + scene + " --out " + out;
  ASSERT_EQ(runGtbake(sweep + " --res 16x16 --spp 8").exit_code, 0);
  const std::string before = readBytes(dir.path() / "cavity.exr");
  ASSERT_FALSE(before.empty());
  // A slow run, killed with SIGKILL after a moment: no destructor or handler gets to run.
  const std::string command = "timeout -s KILL 2 " + std::string(GTBAKE_BINARY) + " " + sweep +
                              " --res 512x512 --spp 4096 >/dev/null 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_NE(status, 0) << "the slow run finished before it could be killed";
  EXPECT_EQ(readBytes(dir.path() / "cavity.exr"), before);
}

}  // namespace
}  // namespace gtbake::test
