// The ranking text of docs/validate_gtso.md §2 is the generated statements of validate_gtso.json
// (/ranking_tests/by_roughness/*/statement, built from /best and the paired scene-level tests),
// verbatim and in roughness order, and each names /best. luts/ by default; GTBAKE_LUTS_DIR
// overrides (to check a fresh run before luts/ is regenerated).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(DocsRanking, TextIsTheGeneratedStatements) {
  const char* env = std::getenv("GTBAKE_LUTS_DIR");
  const std::string luts = env != nullptr ? env : std::string(GTBAKE_SOURCE_DIR) + "/luts";
  const std::string docs = readFile(std::string(GTBAKE_SOURCE_DIR) + "/docs/validate_gtso.md");
  const std::string begin = "<!-- ranking-tests:begin -->\n", end = "<!-- ranking-tests:end -->";
  const auto b = docs.find(begin), e = docs.find(end);
  ASSERT_NE(b, std::string::npos);
  ASSERT_NE(e, std::string::npos);
  std::vector<std::string> lines;
  std::istringstream block(docs.substr(b + begin.size(), e - b - begin.size()));
  for (std::string line; std::getline(block, line);) lines.push_back(line);

  const nlohmann::json j =
      nlohmann::json::parse(readFile(luts + "/validate_gtso/validate_gtso.json"));
  ASSERT_TRUE(j.contains("ranking_tests"))
      << luts << "/validate_gtso/validate_gtso.json predates the tests";
  const std::vector<double> roughness = j.at("sweep").at("roughness").get<std::vector<double>>();
  ASSERT_EQ(lines.size(), roughness.size());
  for (std::size_t k = 0; k < roughness.size(); ++k) {
    char key[8], rp[8];
    std::snprintf(key, sizeof(key), "S%03d", static_cast<int>(std::lround(100 * roughness[k])));
    std::snprintf(rp, sizeof(rp), "%.2f", roughness[k]);
    const nlohmann::json& r = j.at("ranking_tests").at("by_roughness").at(key);
    const std::string statement = r.at("statement").get<std::string>();
    EXPECT_EQ(lines[k], "- r_p " + std::string(rp) + ": " + statement) << key;
    EXPECT_EQ(r.at("best"), j.at("best").at(key)) << key;
    EXPECT_EQ(statement.rfind(j.at("best").at(key).get<std::string>() + " has the lowest RMSE", 0),
              0u)
        << key;
  }
}

// The Eq. 10 verdict's words in docs/fit.md and docs/index.md follow fit.json /shipped/verdict (the
// generated lines and the numbers beside them are checked by gtbake-docs): the bold verdict word,
// and the prose claims "inside the band" and "only near A → 1", which may stand only where the
// verdict by range of A supports them.
TEST(DocsVerdict, WordsFollowFitJson) {
  const char* env = std::getenv("GTBAKE_LUTS_DIR");
  const std::string luts = env != nullptr ? env : std::string(GTBAKE_SOURCE_DIR) + "/luts";
  const nlohmann::json j = nlohmann::json::parse(readFile(luts + "/fit/fit.json"));
  const nlohmann::json& verdict = j.at("shipped").at("verdict");
  const std::string word = verdict.at("verdict").get<std::string>();
  const std::string fit = readFile(std::string(GTBAKE_SOURCE_DIR) + "/docs/fit.md");
  const std::string index = readFile(std::string(GTBAKE_SOURCE_DIR) + "/docs/index.md");
  EXPECT_NE(fit.find("**Verdict on the paper's constants, by range of A: " + word + ".**"),
            std::string::npos)
      << word;
  EXPECT_NE(index.find("the verdict on the paper's constants by range of A is **" + word + "**"),
            std::string::npos)
      << word;
  bool only_near_one = word == "outside";
  for (const nlohmann::json& r : verdict.at("ranges")) {
    if (r.at("verdict") != "outside") continue;
    only_near_one = only_near_one && r.at("set_near_open_limit").get<bool>() &&
                    r.at("max_ratio_below_open_limit").at("value").get<double>() <=
                        r.at("threshold").get<double>();
  }
  for (const std::string* doc : {&fit, &index}) {
    if (word != "consistent") {
      EXPECT_EQ(doc->find("inside the band"), std::string::npos);
    }
    if (!only_near_one) {
      EXPECT_EQ(doc->find("only near A → 1"), std::string::npos);
    }
  }
}

}  // namespace
