#include "docs/verdict_block.h"

#include <cstdio>

#include "common/error.h"

namespace gtbake::docs {

std::string verdictLines(const nlohmann::json& fit) {
  if (!fit.contains("shipped") || !fit.at("shipped").contains("verdict")) {
    throw Error("fit.json has no /shipped/verdict: rerun `gtbake fit`");
  }
  const nlohmann::json& verdict = fit.at("shipped").at("verdict");
  const nlohmann::json& ranges = verdict.at("ranges");
  std::string lines;
  for (std::size_t r = 0; r < ranges.size(); ++r) {
    const nlohmann::json& range = ranges[r];
    char label[96];
    std::snprintf(label, sizeof label, "- A in [%.1f, %.1f%c (%.1f %% of pixels): ",
                  range.at("A_range")[0].get<double>(), range.at("A_range")[1].get<double>(),
                  r + 1 == ranges.size() ? ']' : ')',
                  100.0 * range.at("pixel_share").get<double>());
    lines += label + range.at("text").get<std::string>() + "\n";
  }
  return lines + "- overall: " + verdict.at("headline").get<std::string>() + "\n";
}

std::optional<std::string> withGeneratedBlock(const std::string& text, const std::string& tag,
                                              const std::string& lines) {
  const std::string begin = "<!-- " + tag + ":begin -->\n";
  const std::string end = "<!-- " + tag + ":end -->";
  const std::size_t b = text.find(begin);
  if (b == std::string::npos) return std::nullopt;
  const std::size_t from = b + begin.size();
  const std::size_t e = text.find(end, from);
  if (e == std::string::npos) return std::nullopt;
  return text.substr(0, from) + lines + text.substr(e);
}

}  // namespace gtbake::docs
