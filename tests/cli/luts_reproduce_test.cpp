// luts/ is reproducible: a fresh `gtbake all` gives the committed files back.
//
// On any x86-64 CPU with AVX2 every compared byte is identical (the sweep caps Embree's kernels at
// AVX2, docs/reproducibility.md). On a CPU without AVX2, Embree's narrower kernels may resolve a
// handful of ray/edge ties differently, which moves the path-traced
// sweep (and so the Equation 10 fit derived from it) by amounts far below its standard errors; the
// GTSO tables, u and the BC4 blocks do not depend on Embree and must match exactly. So:
//   - binary tables (.f32, .dds, .ktx2): identical bytes;
//   - gtso/gtso.json: identical numbers (timings aside);
//   - the other text (.json, .h, .hlsl, .glsl, .html, .svg): identical, or every number within
//     the relative tolerance kTolerances gives its file and key (each with its reason), plus one
//     unit in the last printed digit in text files (JSON: timing keys and ray counts, which
//     measure the run, ignored);
//   - the output-set manifests are not compared (*.manifest.json: hashes of files that hold run
//     timings);
//   - the images luts/ does not commit (the per-view EXRs of the sweep and screen-ao, the reports'
//     PNG and SVG pictures): on a CPU with AVX2 their SHA-256 must equal the ones the committed
//     manifests list.
// docs/reproducibility.md explains the tolerances.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "cli_harness.h"
#include "common/atomic_file.h"
#include "common/output_set.h"

namespace gtbake::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// How far a number may move when a regenerated file is not byte-identical, relative to the larger
// of the two values, and why. Measured between this repository's luts/ (written on another
// x86-64 machine) and a fresh run on a 2-core AMD EPYC: gtso.json identical; fit.json coefficients
// moved by <= 1e-6 relative (0.002 SE), their SEs by <= 8.5e-6, the EIV bias estimates by
// <= 4.6e-5, everything else by <= 1.8e-5; sweep.json's mean A by 1.2e-7.
struct Tolerance {
  const char* pattern;  // ECMAScript regex over "file:json-pointer" (text files: "file:")
  double relative;
  const char* reason;
};
// First match wins.
const Tolerance kTolerances[] = {
    {"gtso/.*", 0.0,
     "GTSO tables, u and their errors are computed without Embree: the same bits on any x86-64"},
    {"fit/fit.json:/(linear|linear_uncorrected)/.*", 5e-6,
     "the refit coefficients (measured 1e-6): 5e-6 relative is <= 0.027 SE of each (c0 is "
     "tightest, SE/c0 = 1.9e-4), so no conclusion drawn from them can change"},
    {"fit/fit.json:.*/(linear_se|se|se_iid)/.*", 5e-5,
     "standard errors (measured 8.5e-6) may move by 0.005% of themselves, not by 100%"},
    {"fit/fit.json:/eiv_bias/.*", 1e-3,
     "EIV bias estimates are differences of two fits, so they move far more relative to "
     "themselves than the fits do (measured 2.1e-4 on a0 between two EPYC machines: 2.6e-8 "
     "absolute, 1e-4 of its Monte Carlo SE); 1e-3 still pins each to 0.1% of its value"},
    {"(fit/fit|sweep/sweep|validate_gtso/validate_gtso).json:.*", 1e-4,
     "every other sweep-derived number (errors, per-albedo fits, leave-one-out refits, mean A) "
     "to 0.01%: a few Embree tie flips among ~164 M rays move them far less"},
    {"ship/gtbake_tables.(h|hlsl|glsl):", 1e-5,
     "the headers carry the coefficients (as tight as fit.json's) and u and the tables (exact)"},
    {"fit/report/.*", 2e-4,
     "the report prints every fit.json quantity, the EIV bias ones included"},
};

const Tolerance& toleranceFor(const std::string& where) {
  for (const Tolerance& t : kTolerances) {
    if (std::regex_match(where, std::regex(t.pattern))) return t;
  }
  static const Tolerance kNone{"", 0.0, "no rule for this file: it must be identical"};
  return kNone;
}

// Equal, or within `relative` of the larger magnitude plus `last_digit_unit` (one unit in the last
// printed place of a number printed with few digits: a value on a rounding boundary prints either
// way, e.g. (refit - shipped)/SE = -115.25 prints "-115.3" here and "-115.2" elsewhere).
// `relative` = 0 demands the same value.
bool numbersAgree(double want, double got, double relative, double last_digit_unit) {
  if (want == got) return true;
  if (relative == 0.0) return false;
  return std::abs(want - got) <=
         relative * std::max(std::abs(want), std::abs(got)) + last_digit_unit;
}

// One unit in the last printed digit of a number token, 10^(exponent - decimals): 0.1 for
// "-115.3", 1e-7 for "2.569e-04", 1 for "36864".
double lastDigitUnit(const std::string& token) {
  const std::size_t e = token.find_first_of("eE");
  const std::string mantissa = token.substr(0, e);
  const std::size_t point = mantissa.find('.');
  const int decimals =
      point == std::string::npos
          ? 0
          : static_cast<int>(mantissa.size() - point - 1 - (mantissa.back() == 'f' ? 1 : 0));
  const int exponent = e == std::string::npos ? 0 : std::stoi(token.substr(e + 1));
  return std::pow(10.0, exponent - decimals);
}

// Keys whose values measure the run (time, speed, machine, ray counts), not its results: the
// names above and every "<stage>_s" (seconds: bake_s, fit_s, encode_s, ...). Ray counts are exact
// on one machine but move by a few rays with another CPU's Embree kernels.
bool isVolatileKey(const std::string& key) {
  static const std::regex kPattern(
      ".*(seconds|per_second|timing|threads|elapsed|duration).*|rays|[a-z0-9_]+_s");
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

// Splits text into numbers and the text between them; equal when the text matches exactly and
// every pair of numbers agrees within the file's tolerance and the last printed digit.
bool sameTextWithinTolerance(const std::string& a, const std::string& b, const Tolerance& t,
                             std::string& where) {
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
    // The parts alternate: text, number, text, ...; differing text is a real difference.
    const bool number = i % 2 == 1;
    if (!number ||
        !numbersAgree(std::strtod(pa[i].c_str(), nullptr), std::strtod(pb[i].c_str(), nullptr),
                      t.relative, std::max(lastDigitUnit(pa[i]), lastDigitUnit(pb[i])))) {
      where = "'" + pa[i] + "' vs '" + pb[i] + "' (allowed: " + std::to_string(t.relative) +
              " relative and one unit in the last digit; " + t.reason + ")";
      return false;
    }
  }
  return true;
}

// JSON numbers are written with full round-trip precision, so no last-digit allowance (strings
// that quote rounded numbers get it). `where`
// is "file:pointer" of `a` and `b` and names the first difference on return.
bool sameJson(const json& a, const json& b, std::string& where) {
  if (a.is_number() && b.is_number()) {
    const Tolerance& t = toleranceFor(where);
    if (numbersAgree(a.get<double>(), b.get<double>(), t.relative, 0.0)) return true;
    where += " (" + a.dump() + " vs " + b.dump() + "; allowed: " + std::to_string(t.relative) +
             " relative, " + t.reason + ")";
    return false;
  }
  if (a.type() != b.type() || a.size() != b.size()) return false;
  if (a.is_object()) {
    for (const auto& [key, child] : a.items()) {
      if (!b.contains(key)) return false;
      std::string inner = where + "/" + key;
      if (!sameJson(child, b.at(key), inner)) {
        where = inner;
        return false;
      }
    }
    return true;
  }
  if (a.is_array()) {
    for (size_t i = 0; i < a.size(); ++i) {
      std::string inner = where + "/" + std::to_string(i);
      if (!sameJson(a[i], b[i], inner)) {
        where = inner;
        return false;
      }
    }
    return true;
  }
  // Strings may quote numbers (a verdict "2.09 <= 2.45"): compared as text under the key's rule.
  if (a.is_string() && b.is_string()) {
    std::string detail;
    if (sameTextWithinTolerance(a.get<std::string>(), b.get<std::string>(), toleranceFor(where),
                                detail)) {
      return true;
    }
    where += " (" + detail + ")";
    return false;
  }
  return a == b;
}

// Compares every compared file of `committed` with its regenerated copy in `fresh`.
void expectSameOutputs(const fs::path& committed, const fs::path& fresh) {
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
    const fs::path other = fresh / relative;
    ASSERT_TRUE(fs::exists(other)) << relative << " was not produced by gtbake all";
    const std::string want = readBytes(entry.path());
    const std::string got = readBytes(other);
    ++compared;
    if (want == got) continue;
    std::string where = relative.generic_string() + ":";
    if (kBinary.count(ext)) {
      ADD_FAILURE() << relative << ": bytes differ";
    } else if (ext == ".json") {
      EXPECT_TRUE(
          sameJson(stripVolatile(json::parse(want)), stripVolatile(json::parse(got)), where))
          << "differs at " << where;
    } else {
      EXPECT_TRUE(sameTextWithinTolerance(want, got, toleranceFor(where), where))
          << relative << " differs: " << where;
    }
  }
  EXPECT_GE(compared, 8u);
}

// luts/ does not commit the per-view EXRs of the sweep and screen-ao, nor the reports' pictures
// (PNG, SVG) and pages (docs/reproducibility.md "What luts/ keeps"), but the committed manifests
// keep each one's SHA-256: on a CPU with AVX2 the fresh run must write those exact bytes for every
// image (the pages are verified as members of their fresh sets below).
void expectSameUncommittedImages(const fs::path& committed, const fs::path& fresh) {
  static const std::set<std::string> kImages = {".exr", ".png", ".svg"};
  int checked = 0;
  for (const auto& entry : fs::recursive_directory_iterator(committed)) {
    const std::string name = entry.path().filename().string();
    const std::string suffix = ".manifest.json";
    if (name.size() <= suffix.size() ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
      continue;
    }
    const fs::path dir = fs::relative(entry.path().parent_path(), committed);
    const std::string command = name.substr(0, name.size() - suffix.size());
    const json want = json::parse(readBytes(entry.path()));
    const OutputManifest got = readOutputSet(fresh / dir, command);
    for (const json& file : want["files"]) {
      const std::string member = file["name"].get<std::string>();
      // Never committed (luts/.gitignore), though a working tree may hold them from a run.
      if (!kImages.count(fs::path(member).extension().string())) continue;
      const OutputFile* found = got.find(member);
      ASSERT_NE(found, nullptr) << dir / member;
      EXPECT_EQ(found->sha256, file["sha256"].get<std::string>()) << dir / member;
      got.readVerified(member);  // the fresh file is what its manifest says
      ++checked;
    }
  }
  EXPECT_GT(checked, 0);
}

// Every page of the layout links only files in its own folder or below (docs/reproducibility.md
// "Layout"): no "../" anywhere in a page, so a report can be moved or served on its own.
void expectRelocatableReports(const fs::path& out) {
  int pages = 0;
  for (const auto& entry : fs::recursive_directory_iterator(out)) {
    if (entry.path().extension() != ".html") continue;
    EXPECT_EQ(readBytes(entry.path()).find("../"), std::string::npos) << entry.path();
    ++pages;
  }
  EXPECT_GE(pages, 4);
}

// `gtbake report` draws every picture and page of a fresh run again from its data files, each the
// bytes `gtbake all` wrote (docs/reproducibility.md "Reports from the data").
void expectReportRedrawsPictures(const fs::path& out) {
  const TempDir drawn("report");
  const RunResult run =
      runGtbake("report --quiet --luts " + out.string() + " --out " + drawn.path().string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  int pictures = 0;
  for (const auto& entry : fs::recursive_directory_iterator(drawn.path())) {
    if (!entry.is_regular_file()) continue;
    const fs::path relative = fs::relative(entry.path(), drawn.path());
    EXPECT_EQ(readBytes(entry.path()), readBytes(out / relative)) << relative;
    ++pictures;
  }
  EXPECT_GT(pictures, 100);
}

TEST(Luts, FreshAllReproducesCommittedLuts) {
  const fs::path committed = fs::path(GTBAKE_SOURCE_DIR) / "luts";
  ASSERT_TRUE(fs::exists(committed / "ship" / "gtbake_tables.h")) << "luts/ has not been generated";
  const TempDir fresh("luts");
  const RunResult run = runGtbake("all --quiet --out " + fresh.path().string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  expectSameOutputs(committed, fresh.path());
  // Without AVX2, Embree's narrower kernels may flip a few ray ties (see the top of this file).
  if (__builtin_cpu_supports("avx2")) expectSameUncommittedImages(committed, fresh.path());
  // The HTML pages and their images belong to their commands' output sets, verified like the
  // JSON beside them.
  const std::pair<const char*, const char*> pages[] = {
      {"fit", "report/index.html"},
      {"validate_gtso", "report/validate_gtso.html"},
      {"validate_gtso", "report/validate_gtso_cavity_0.png"},
      {"index", "index.html"}};
  for (const auto& [command, page] : pages) {
    const fs::path dir = std::string(command) == "index" ? fresh.path() : fresh.path() / command;
    const OutputManifest set = readOutputSet(dir, command);
    ASSERT_NE(set.find(page), nullptr) << command << " " << page;
    EXPECT_EQ(set.readVerified(page), readFile(dir / page));
  }
  expectRelocatableReports(fresh.path());
  expectReportRedrawsPictures(fresh.path());
  const OutputManifest screen = readOutputSet(fresh.path() / "screen_ao", "screen_ao");
  ASSERT_NE(screen.find("screen_ao.html"), nullptr);
  EXPECT_EQ(screen.readVerified("screen_ao.html"),
            readFile(fresh.path() / "screen_ao" / "screen_ao.html"));
}

// The tolerances accept what another machine's Embree does to luts/, and no more: a change of a
// standard error, of u or of one coefficient by 0.1% is caught, and so is a reworded text.
TEST(Luts, TolerancesCatchRealChanges) {
  const fs::path committed = fs::path(GTBAKE_SOURCE_DIR) / "luts";
  std::string where = "fit/fit.json:";
  const json fit = json::parse(readBytes(committed / "fit" / "fit.json"));
  EXPECT_TRUE(sameJson(fit, fit, where));
  const auto changed = [&](const std::string& file, const std::string& pointer, double factor) {
    json doc = json::parse(readBytes(committed / file));
    doc[json::json_pointer(pointer)] = doc[json::json_pointer(pointer)].get<double>() * factor;
    std::string at = file + ":";
    return !sameJson(json::parse(readBytes(committed / file)), doc, at);
  };
  EXPECT_TRUE(changed("fit/fit.json", "/linear/c0", 1.0 + 1e-3));
  EXPECT_FALSE(changed("fit/fit.json", "/linear/c0", 1.0 + 1e-6));  // what another CPU does
  EXPECT_TRUE(changed("fit/fit.json", "/linear_se/b1", 1.01));
  EXPECT_TRUE(changed("fit/fit.json", "/eiv_bias/linear/a0", 1.01));
  EXPECT_TRUE(changed("gtso/gtso.json", "/cone/u", 1.0 + 1e-12));
  EXPECT_TRUE(changed("gtso/gtso.json", "/cone/u_se", 1.0 + 1e-12));
  const Tolerance& report = toleranceFor("fit/report/index.html:");
  std::string at;
  EXPECT_TRUE(sameTextWithinTolerance("<td>-115.3</td>", "<td>-115.2</td>", report, at));
  EXPECT_FALSE(sameTextWithinTolerance("<td>-115.3</td>", "<td>-115.1</td>", report, at));
  EXPECT_FALSE(sameTextWithinTolerance("<td>0.00113</td>", "<td>0.00226</td>", report, at));
  EXPECT_FALSE(sameTextWithinTolerance("SE 0.5", "se 0.5", report, at));
  std::string verdict = "fit/fit.json:/shipped/against_band/verdict";
  EXPECT_TRUE(
      sameJson(json("consistent: 2.09 <= 2.45"), json("consistent: 2.10 <= 2.45"), verdict));
  verdict = "fit/fit.json:/shipped/against_band/verdict";
  EXPECT_FALSE(sameJson(json("consistent: 2.09"), json("inconsistent: 2.09"), verdict));
}

}  // namespace
}  // namespace gtbake::test
