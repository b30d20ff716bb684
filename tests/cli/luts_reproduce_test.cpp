// luts/ is reproducible: a fresh `gtbake all` gives the committed files back.
//
// On this kind of machine every compared byte is identical. Elsewhere, another CPU's Embree kernels
// may resolve a handful of ray/edge ties differently, which moves the path-traced sweep (and so
// the Equation 10 fit derived from it) by amounts far below its standard errors; the GTSO tables
// and BC4 blocks do not depend on Embree and must match exactly. So the check is:
//   - binary tables (.f32, .dds, .ktx2): identical bytes;
//   - text (.json, .h, .hlsl, .glsl, .html, .svg): identical, or identical once numbers are
//     compared within kNumericTolerance (JSON: timing keys, which are measurements of the run and
//     not results, are ignored);
//   - PNG previews are pictures of the compared data and are not compared, nor are the
//     output-set manifests (*.manifest.json: hashes of files that hold run timings).
// docs/reproducibility.md explains the tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "cli_harness.h"

namespace gtbake::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Absolute tolerance on any number in a text artifact when bytes differ: 1e-3 is a fifth of the
// 0.005 bar on the fit's standard errors, so a difference within it cannot change a conclusion.
constexpr double kNumericTolerance = 1e-3;

// Keys whose values measure the run (time, speed, machine, ray counts), not its results. Ray
// counts are exact on one machine but move by a few rays with another CPU's Embree kernels.
bool isVolatileKey(const std::string& key) {
  static const std::regex kPattern(".*(seconds|per_second|timing|threads|elapsed|duration).*|rays");
  return std::regex_match(key, kPattern);
}

json stripVolatile(const json& value) {
  if (value.is_object()) {
    json out = json::object();
    for (const auto& [key, child] : value.items()) {
      if (!isVolatileKey(key)) out[key] = stripVolatile(child);
    }
    return out;
  }
  if (value.is_array()) {
    json out = json::array();
    for (const auto& child : value) out.push_back(stripVolatile(child));
    return out;
  }
  return value;
}

bool sameJson(const json& a, const json& b, std::string& where) {
  if (a.is_number() && b.is_number()) {
    if (std::abs(a.get<double>() - b.get<double>()) <= kNumericTolerance) return true;
    where += " (" + a.dump() + " vs " + b.dump() + ")";
    return false;
  }
  if (a.type() != b.type() || a.size() != b.size()) return false;
  if (a.is_object()) {
    for (const auto& [key, child] : a.items()) {
      if (!b.contains(key)) return false;
      std::string inner = where + "." + key;
      if (!sameJson(child, b.at(key), inner)) {
        where = inner;
        return false;
      }
    }
    return true;
  }
  if (a.is_array()) {
    for (size_t i = 0; i < a.size(); ++i) {
      std::string inner = where + "[" + std::to_string(i) + "]";
      if (!sameJson(a[i], b[i], inner)) {
        where = inner;
        return false;
      }
    }
    return true;
  }
  return a == b;
}

// Splits text into numbers and the text between them; equal when the text matches exactly and
// every pair of numbers agrees within kNumericTolerance.
bool sameTextWithinTolerance(const std::string& a, const std::string& b, std::string& where) {
  static const std::regex kNumber(R"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?f?)");
  auto split = [](const std::string& text) {
    std::vector<std::string> parts;
    std::sregex_token_iterator it(text.begin(), text.end(), kNumber, {-1, 0});
    for (; it != std::sregex_token_iterator(); ++it) parts.push_back(*it);
    return parts;
  };
  const auto pa = split(a);
  const auto pb = split(b);
  if (pa.size() != pb.size()) return false;
  for (size_t i = 0; i < pa.size(); ++i) {
    if (pa[i] == pb[i]) continue;
    char* end_a = nullptr;
    char* end_b = nullptr;
    const double va = std::strtod(pa[i].c_str(), &end_a);
    const double vb = std::strtod(pb[i].c_str(), &end_b);
    if (end_a == pa[i].c_str() || end_b == pb[i].c_str() || std::abs(va - vb) > kNumericTolerance) {
      where = "'" + pa[i] + "' vs '" + pb[i] + "'";
      return false;
    }
  }
  return true;
}

TEST(Luts, FreshAllReproducesCommittedLuts) {
  const fs::path committed = fs::path(GTBAKE_SOURCE_DIR) / "luts";
  ASSERT_TRUE(fs::exists(committed / "gtbake_tables.h")) << "luts/ has not been generated";
  const TempDir fresh("luts");
  const RunResult run = runGtbake("all --quiet --out " + fresh.path().string());
  ASSERT_EQ(run.exit_code, 0) << run.err;

  static const std::set<std::string> kBinary = {".f32", ".dds", ".ktx2"};
  static const std::set<std::string> kText = {".json", ".h", ".hlsl", ".glsl", ".html", ".svg"};
  size_t compared = 0;
  for (const auto& entry : fs::recursive_directory_iterator(committed)) {
    if (!entry.is_regular_file()) continue;
    const fs::path relative = fs::relative(entry.path(), committed);
    const std::string ext = relative.extension().string();
    if (!kBinary.count(ext) && !kText.count(ext)) continue;
    // Output-set manifests hash files that hold timings; what they list is compared above.
    const std::string name = relative.filename().string();
    if (name.size() > 14 && name.compare(name.size() - 14, 14, ".manifest.json") == 0) continue;
    const fs::path other = fresh.path() / relative;
    ASSERT_TRUE(fs::exists(other)) << relative << " was not produced by gtbake all";
    const std::string want = readBytes(entry.path());
    const std::string got = readBytes(other);
    ++compared;
    if (want == got) continue;
    std::string where;
    if (kBinary.count(ext)) {
      ADD_FAILURE() << relative << ": bytes differ";
    } else if (ext == ".json") {
      EXPECT_TRUE(
          sameJson(stripVolatile(json::parse(want)), stripVolatile(json::parse(got)), where))
          << relative << " differs at " << where;
    } else {
      EXPECT_TRUE(sameTextWithinTolerance(want, got, where)) << relative << " differs: " << where;
    }
  }
  EXPECT_GE(compared, 8u);
}

}  // namespace
}  // namespace gtbake::test
