#include "pipeline/option_values.h"

#include <cmath>
#include <cstdlib>
#include <regex>
#include <vector>

#include "common/error.h"

namespace gtbake {

std::pair<int, int> parseResolution(const std::string& text) {
  static const std::regex kPattern("([0-9]{1,6})x([0-9]{1,6})");
  std::smatch match;
  if (!std::regex_match(text, match, kPattern)) {
    throw Error("--res must look like WxH (e.g. 256x256), got '" + text + "'");
  }
  // At most six digits each, so both fit an int; the sweep checks the range (kMaxResolution).
  return {std::stoi(match[1]), std::stoi(match[2])};
}

MultiBounceCoeffs parseCoeffs(const std::string& text) {
  std::vector<std::string> items;
  for (size_t start = 0;;) {
    const size_t comma = text.find(',', start);
    items.push_back(text.substr(start, comma == std::string::npos ? comma : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (items.size() != 6) {
    throw Error("--coeffs needs six comma-separated numbers a1,a0,b1,b0,c1,c0; got " +
                std::to_string(items.size()));
  }
  MultiBounceCoeffs coeffs{};
  for (size_t i = 0; i < items.size(); ++i) {
    char* end = nullptr;
    coeffs[i] = std::strtod(items[i].c_str(), &end);
    if (items[i].empty() || *end != '\0' || !std::isfinite(coeffs[i])) {
      throw Error("--coeffs: '" + items[i] + "' is not a finite number");
    }
  }
  return coeffs;
}

}  // namespace gtbake
