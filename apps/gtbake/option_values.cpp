#include "option_values.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <regex>
#include <vector>

#include "common/error.h"
#include "screen_ao/screen_ao_import.h"
#include "screen_ao/screen_ao_settings.h"
#include "sweep/sweep_command.h"

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

MultiBounceCoeffs parseCoeffs(const std::string& text, const std::string& option) {
  std::vector<std::string> items;
  for (size_t start = 0;;) {
    const size_t comma = text.find(',', start);
    items.push_back(text.substr(start, comma == std::string::npos ? comma : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (items.size() != 6) {
    throw Error(option + " needs six comma-separated numbers a1,a0,b1,b0,c1,c0; got " +
                std::to_string(items.size()));
  }
  MultiBounceCoeffs coeffs{};
  for (size_t i = 0; i < items.size(); ++i) {
    char* end = nullptr;
    coeffs[i] = std::strtod(items[i].c_str(), &end);
    if (items[i].empty() || *end != '\0' || !std::isfinite(coeffs[i])) {
      throw Error(option + ": '" + items[i] + "' is not a finite number");
    }
  }
  return coeffs;
}

std::uint64_t parseSeed(const std::string& text, const std::string& option) {
  if (text.empty() || text.size() > 20 ||
      text.find_first_not_of("0123456789") != std::string::npos) {
    throw Error(option + " must be an integer in [0, 2^64 - 1], got '" + text + "'");
  }
  errno = 0;
  const unsigned long long value = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE) {
    throw Error(option + " must be an integer in [0, 2^64 - 1], got '" + text + "'");
  }
  return value;
}

std::pair<int, int> parseShard(const std::string& text) {
  static const std::regex kPattern("([0-9]{1,6})/([0-9]{1,6})");
  std::smatch match;
  if (!std::regex_match(text, match, kPattern)) {
    throw Error("--shard must look like I/N (shard I of N, 0 <= I < N), got '" + text + "'");
  }
  const int index = std::stoi(match[1]);
  const int count = std::stoi(match[2]);
  if (count < 1 || count > kMaxShards || index >= count) {
    throw Error("--shard must be I/N with 0 <= I < N <= " + std::to_string(kMaxShards) + ", got '" +
                text + "'");
  }
  return {index, count};
}

namespace {

// "none" (empty) or comma-separated finite numbers each passing `valid`; `error` otherwise.
std::vector<double> parseNumberList(const std::string& text, bool (*valid)(double),
                                    const std::string& error) {
  if (text == "none") return {};
  std::vector<double> values;
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = text.find(',', begin);
    const std::string item = text.substr(begin, end == std::string::npos ? end : end - begin);
    char* stop = nullptr;
    const double v = std::strtod(item.c_str(), &stop);
    if (item.empty() || stop != item.c_str() + item.size() || !std::isfinite(v) || !valid(v)) {
      throw Error(error + ", got '" + text + "'");
    }
    values.push_back(v);
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  return values;
}

}  // namespace

AoInput parseAoInput(const std::string& estimator, const std::string& screen_ao,
                     const std::string& truth, const std::filesystem::path& sweep) {
  AoInput input;
  if (truth != "near" && truth != "unbounded") {
    throw Error("--truth must be near or unbounded, got '" + truth + "'");
  }
  input.unbounded_truth = truth == "unbounded";
  if (estimator.empty()) {
    if (!screen_ao.empty()) throw Error("--screen-ao needs --estimator (which estimator's A)");
    return input;
  }
  if (!isEstimatorName(estimator)) {
    std::string list;
    for (const std::string& n : screenAoEstimatorNames()) list += (list.empty() ? "" : ", ") + n;
    throw Error("--estimator '" + estimator + "' is not a screen-ao estimator (" + list +
                ", or a name given to `gtbake screen-ao --import`)");
  }
  input.estimator = estimator;
  input.screen_ao = screen_ao.empty() ? sweep / "screen_ao" : std::filesystem::path(screen_ao);
  return input;
}

std::vector<double> parseGbufferRadii(const std::string& text) {
  return parseNumberList(
      text, [](double v) { return v > 0.0; },
      "--gbuffer-radius must be 'none' or comma-separated positive metres");
}

std::vector<double> parseSpecularRoughness(const std::string& text) {
  // The range is the sweep's own option check.
  return parseNumberList(
      text, [](double) { return true; },
      "--specular-roughness must be 'none' or comma-separated numbers in [0, 1]");
}

}  // namespace gtbake
