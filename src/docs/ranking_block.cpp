#include "docs/ranking_block.h"

#include <cmath>
#include <cstdio>

#include "common/error.h"
#include "docs/verdict_block.h"

namespace gtbake::docs {

std::string rankingLines(const nlohmann::json& validate_gtso) {
  if (!validate_gtso.contains("ranking_tests") || !validate_gtso.contains("sweep")) {
    throw Error("validate_gtso.json has no ranking_tests: rerun `gtbake validate-gtso`");
  }
  std::string lines;
  for (const nlohmann::json& r : validate_gtso.at("sweep").at("roughness")) {
    const double rp = r.get<double>();
    char key[16], label[16];
    std::snprintf(key, sizeof(key), "S%03d", static_cast<int>(std::lround(100 * rp)));
    std::snprintf(label, sizeof(label), "%.2f", rp);
    const nlohmann::json& tests = validate_gtso.at("ranking_tests").at("by_roughness");
    if (!tests.contains(key))
      throw Error(std::string("validate_gtso.json has no ranking for ") + key);
    lines += "- r_p " + std::string(label) + ": " +
             tests.at(key).at("statement").get<std::string>() + "\n";
  }
  return lines;
}

std::optional<std::string> withRankingBlock(const std::string& text, const std::string& lines) {
  return withGeneratedBlock(text, "ranking-tests", lines);
}

}  // namespace gtbake::docs
