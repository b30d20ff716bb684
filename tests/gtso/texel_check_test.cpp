// The sampled texel check of `gtbake gtso` (gtso/texel_check.h): its lines are a proper sample,
// and its errors are those of the full --reference-factor comparison at the sampled texels.
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "common/atomic_file.h"
#include "gtso/gtso_command.h"
#include "gtso/gtso_tables.h"
#include "gtso/texel_check.h"

namespace gtbake::gtso {
namespace {

TEST(TexelCheck, SampledLinesAreDistinctDeterministicAndSeeded) {
  for (int dims : {3, 4}) {
    const std::vector<std::size_t> a = sampleLines(dims, 32, 64, 1);
    EXPECT_EQ(a, sampleLines(dims, 32, 64, 1));
    EXPECT_NE(a, sampleLines(dims, 32, 64, 2));
    EXPECT_EQ(std::set<std::size_t>(a.begin(), a.end()).size(), a.size());
    EXPECT_TRUE(std::is_sorted(a.begin(), a.end()));
    EXPECT_LT(a.back(), 32u * 32u);
    const std::vector<std::size_t> all = sampleLines(dims, 8, 64, 7);
    for (std::size_t i = 0; i < all.size(); ++i) EXPECT_EQ(all[i], i);  // every line once
  }
  EXPECT_NE(sampleLines(3, 32, 16, 1), sampleLines(4, 32, 16, 1));  // distinct streams
  EXPECT_ANY_THROW(sampleLines(3, 8, 65, 1));
}

// The sample of every run: half from the edge stratum (theta_o texels at both ends), half from the
// interior, distinct; every line when asked for at least N^2; the check splits its texels by
// stratum.
TEST(TexelCheck, StratifiedSampleTakesHalfFromTheEdgeColumns) {
  const std::vector<std::size_t> s = sampleStratifiedLines(4, 32, 16, 1);
  ASSERT_EQ(s.size(), 16u);
  EXPECT_EQ(std::set<std::size_t>(s.begin(), s.end()).size(), 16u);
  EXPECT_EQ(std::count_if(s.begin(), s.end(), [](std::size_t l) { return isEdgeLine(32, l); }), 8);
  EXPECT_TRUE(isEdgeLine(32, 5 * 32 + 0) && isEdgeLine(32, 5 * 32 + 31) &&
              !isEdgeLine(32, 5 * 32 + 3) && !isEdgeLine(32, 5 * 32 + 28));
  EXPECT_EQ(sampleStratifiedLines(3, 8, 64, 1).size(), 64u);
  EXPECT_EQ(sampleStratifiedLines(3, 8, 100, 1).size(), 64u);
  // Size 8: 48 edge lines and 16 interior ones; of 40, the interior gives all 16, the edge 24.
  const std::vector<std::size_t> t = sampleStratifiedLines(3, 8, 40, 2);
  EXPECT_EQ(std::count_if(t.begin(), t.end(), [](std::size_t l) { return !isEdgeLine(8, l); }), 16);
  const Table table = bakeTable(3, 8, 8, nullptr);
  const TexelCheck c = checkTexels(table, 8, kTexelCheckFactor, t, 2, nullptr);
  EXPECT_EQ(c.strata[0].lines, 24u);
  EXPECT_EQ(c.strata[1].lines, 16u);
  EXPECT_EQ(c.strata[0].texels + c.strata[1].texels, c.texels);
  EXPECT_EQ(std::max(c.strata[0].max, c.strata[1].max), c.max);
}

// At size 8 the sampled check at the sampled texels equals the full 4x reference (what
// `--reference-factor 4` bakes) at those texels: same maximum, same RMS, same worst texel.
TEST(TexelCheck, AgreesWithTheFullReferenceAtTheSampledTexels) {
  constexpr int kSize = 8, kCells = 8;
  for (int dims : {3, 4}) {
    const Table t = bakeTable(dims, kSize, kCells, nullptr);
    const Table full = bakeTable(dims, kSize, kCells * kTexelCheckFactor, nullptr);
    const std::vector<std::size_t> lines = sampleLines(dims, kSize, 10, 3);
    const TexelCheck c = checkTexels(t, kCells, kTexelCheckFactor, lines, 3, nullptr);
    double max = 0.0, sum2 = 0.0;
    std::size_t n = 0;
    std::array<int, 4> worst{};
    for (std::size_t line : lines) {
      for (const auto& i : lineTexels(dims, kSize, line)) {
        const double d = std::abs(t.values[t.index(i)] - full.values[t.index(i)]);
        if (d > max || n == 0) {
          max = d;
          worst = i;
        }
        sum2 += d * d;
        ++n;
      }
    }
    EXPECT_EQ(c.texels, n);
    EXPECT_EQ(n, 10u * (dims == 3 ? kSize : kSize * kSize));
    EXPECT_EQ(c.max, max) << dims;
    EXPECT_DOUBLE_EQ(c.rms, std::sqrt(sum2 / static_cast<double>(n))) << dims;
    EXPECT_EQ(c.worst_index, worst);
    EXPECT_EQ(c.worst_reference, full.values[t.index(worst)]);
    EXPECT_GT(c.max, 0.0);  // a coarse 8-cell lobe grid is not exact
  }
}

// Through the command: with every line sampled, gtso.json's texel check equals its full
// --reference-factor 4 comparison; with the default sample it reports its lines and seed.
TEST(TexelCheck, CommandReportsTheCheckAndMatchesTheFullReference) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("gtbake_test_texel_check_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  GtsoOptions o;
  o.out = dir;
  o.size = 8;
  o.lobe_cells = 8;
  o.error_lobes = 8;
  o.error_seeds = 1;
  o.progress = false;
  o.reference_factor = 4;
  o.closed_form_lobes = 64;  // the closed form is not what this checks (s3_closed_form_test.cpp)
  o.texel_check_lines_3d = 64;
  o.texel_check_lines_4d = 64;
  runGtso(o);
  auto json = nlohmann::json::parse(readFile(dir / "gtso.json"));
  for (const char* key : {"3d", "4d"}) {
    const auto& t = json["tables"][key];
    EXPECT_EQ(t["texel_check"]["lines"], 64);
    EXPECT_EQ(t["texel_check"]["max_abs"].get<double>(),
              t["max_abs_error_vs_reference"].get<double>())
        << key;
    EXPECT_NEAR(t["texel_check"]["rms"].get<double>(), t["rms_error_vs_reference"].get<double>(),
                1e-15)
        << key;
  }
  std::filesystem::remove_all(dir);
  o.reference_factor = 0;
  o.texel_check_lines_3d = 5;
  o.texel_check_lines_4d = 3;
  runGtso(o);
  json = nlohmann::json::parse(readFile(dir / "gtso.json"));
  const auto& c4 = json["tables"]["4d"]["texel_check"];
  EXPECT_EQ(c4["strata"]["edge"]["lines"].get<int>() + c4["strata"]["interior"]["lines"].get<int>(),
            3);
  EXPECT_EQ(c4["lines"], 3);
  EXPECT_EQ(c4["texels"], 3 * 64);
  EXPECT_EQ(c4["seed"], 1);
  EXPECT_EQ(c4["line_indices"].size(), 3u);
  EXPECT_EQ(json["tables"]["3d"]["texel_check"]["texels"], 5 * 8);
  const std::string exact = json["end_to_end"]["points"]["exact"];
  EXPECT_NE(exact.find("measured"), std::string::npos) << exact;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gtbake::gtso
