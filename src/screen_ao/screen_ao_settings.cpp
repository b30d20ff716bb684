#include "screen_ao/screen_ao_settings.h"

#include <algorithm>

#include "common/error.h"

namespace gtbake {

const std::vector<Estimator>& screenAoEstimators() {
  static const std::vector<Estimator> list = [] {
    std::vector<Estimator> out;
    for (const EstimatorDescriptor& d : estimatorDescriptors()) out.push_back(d.id);
    return out;
  }();
  return list;
}

const std::vector<std::string>& screenAoEstimatorNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const EstimatorDescriptor& d : estimatorDescriptors()) out.emplace_back(d.name);
    return out;
  }();
  return names;
}

std::vector<Estimator> parseEstimatorList(const std::string& text) {
  if (text == "all") return screenAoEstimators();
  if (text == "none") return {};  // only imported passes (docs/screen_ao.md §8)
  std::vector<Estimator> list;
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = text.find(',', begin);
    const std::string word = text.substr(begin, end == std::string::npos ? end : end - begin);
    const std::optional<Estimator> e = findEstimator(word);
    if (!e) {
      throw Error("--estimators: unknown estimator '" + word +
                  "' (known: " + estimatorListText(screenAoEstimators(), ", ") + ", all or none)");
    }
    if (std::find(list.begin(), list.end(), *e) != list.end()) {
      throw Error("--estimators: '" + word + "' is listed twice");
    }
    list.push_back(*e);
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  return list;
}

std::string estimatorListText(const std::vector<Estimator>& list, const std::string& separator) {
  std::string text;
  for (const Estimator e : list) text += (text.empty() ? "" : separator) + describe(e).name;
  return text;
}

void applySetting(ScreenAoSettings* s, const std::string& text) {
  const std::size_t dot = text.find('.');
  const std::size_t eq = text.find('=');
  if (dot == std::string::npos || eq == std::string::npos || eq < dot) {
    throw Error("--setting must look like ESTIMATOR.KEY=VALUE, got '" + text + "'");
  }
  const std::string estimator = text.substr(0, dot);
  const std::string key = text.substr(dot + 1, eq - dot - 1);
  const std::string value = text.substr(eq + 1);
  if (estimator == "all" && key == "radius") {
    for (const std::string& name : screenAoEstimatorNames()) {
      applySetting(s, name + ".radius=" + value);
    }
    return;
  }
  if (!findEstimator(estimator)) {
    throw Error("--setting: unknown estimator '" + estimator + "' in '" + text + "'");
  }
  describe(estimator, "--setting").apply(s, key, value, text);
}

void validateSettings(const ScreenAoSettings& s) {
  validate(s.reference);
  validate(s.runtime);
  validate(s.hbao);
  validate(s.bitmask_uniform);
  validate(s.bitmask_cosine);
}

nlohmann::ordered_json settingsJson(const ScreenAoSettings& s, Estimator estimator) {
  return describe(estimator).settings(s);
}

double estimatorRadius(const ScreenAoSettings& s, Estimator estimator) {
  return settingsJson(s, estimator).at("radius").get<double>();
}

AoEstimate runEstimator(const ScreenAoSettings& s, Estimator estimator, const GBuffer& g) {
  return describe(estimator).run(s, g);
}

}  // namespace gtbake
