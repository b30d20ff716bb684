#include "screen_ao/screen_ao_settings.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "common/error.h"

namespace gtbake {

namespace {

double parseNumber(const std::string& text, const std::string& setting) {
  char* stop = nullptr;
  const double v = std::strtod(text.c_str(), &stop);
  if (text.empty() || stop != text.c_str() + text.size() || !std::isfinite(v)) {
    throw Error("--setting " + setting + ": '" + text + "' is not a finite number");
  }
  return v;
}

int parseInteger(const std::string& text, const std::string& setting) {
  const double v = parseNumber(text, setting);
  if (v != std::floor(v) || std::abs(v) > 1e9) {
    throw Error("--setting " + setting + ": '" + text + "' is not an integer");
  }
  return static_cast<int>(v);
}

[[noreturn]] void unknownKey(const std::string& estimator, const std::string& key,
                             const char* keys) {
  throw Error("--setting: " + estimator + " has no setting '" + key + "' (it has " + keys + ")");
}

void applyBitmask(BitmaskSettings* b, const std::string& name, const std::string& key,
                  const std::string& value, const std::string& setting) {
  if (key == "radius") {
    b->radius = parseNumber(value, setting);
  } else if (key == "slices") {
    b->slices = parseInteger(value, setting);
  } else if (key == "steps") {
    b->steps = parseInteger(value, setting);
  } else if (key == "thickness") {
    b->thickness = parseNumber(value, setting);
  } else {
    unknownKey(name, key, "radius, slices, steps, thickness");
  }
}

void applyRuntime(GtaoRuntimeSettings* r, const std::string& key, const std::string& value,
                  const std::string& setting) {
  if (key == "radius") {
    r->radius = parseNumber(value, setting);
  } else if (key == "directions") {
    r->directions = parseInteger(value, setting);
  } else if (key == "steps") {
    r->steps = parseInteger(value, setting);
  } else if (key == "thin_compensation") {
    r->thin_compensation = parseNumber(value, setting);
  } else if (key == "intensity") {
    r->intensity = parseNumber(value, setting);
  } else if (key == "temporal_blend") {
    r->temporal_blend = parseNumber(value, setting);
  } else if (key == "frames") {
    r->frames = parseInteger(value, setting);
  } else if (key == "blur") {
    if (value != "0" && value != "1") throw Error("--setting " + setting + ": blur is 0 or 1");
    r->blur = value == "1";
  } else {
    unknownKey("gtao-runtime", key,
               "radius, directions, steps, thin_compensation, intensity, temporal_blend, frames, "
               "blur");
  }
}

}  // namespace

const std::vector<std::string>& screenAoEstimatorNames() {
  static const std::vector<std::string> names = {"gtao-reference", "gtao-runtime", "hbao",
                                                 "bitmask-uniform", "bitmask-cosine"};
  return names;
}

std::vector<std::string> parseEstimatorList(const std::string& text) {
  if (text == "all") return screenAoEstimatorNames();
  if (text == "none") return {};  // only imported passes (docs/screen_ao.md §8)
  std::vector<std::string> list;
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = text.find(',', begin);
    const std::string word = text.substr(begin, end == std::string::npos ? end : end - begin);
    const auto& known = screenAoEstimatorNames();
    if (std::find(known.begin(), known.end(), word) == known.end()) {
      throw Error("--estimators: unknown estimator '" + word +
                  "' (known: gtao-reference, gtao-runtime, hbao, bitmask-uniform, "
                  "bitmask-cosine, all or none)");
    }
    if (std::find(list.begin(), list.end(), word) != list.end()) {
      throw Error("--estimators: '" + word + "' is listed twice");
    }
    list.push_back(word);
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  return list;
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
  } else if (estimator == "gtao-reference") {
    if (key == "radius") {
      s->reference.radius = parseNumber(value, text);
    } else if (key == "slices") {
      s->reference.slices = parseInteger(value, text);
    } else if (key == "refine_tolerance") {
      s->reference.refine_tolerance = parseNumber(value, text);
    } else if (key == "refine_levels") {
      s->reference.refine_levels = parseInteger(value, text);
    } else {
      unknownKey(estimator, key, "radius, slices, refine_tolerance, refine_levels");
    }
  } else if (estimator == "gtao-runtime") {
    applyRuntime(&s->runtime, key, value, text);
  } else if (estimator == "hbao") {
    if (key == "radius") {
      s->hbao.radius = parseNumber(value, text);
    } else if (key == "directions") {
      s->hbao.directions = parseInteger(value, text);
    } else if (key == "steps") {
      s->hbao.steps = parseInteger(value, text);
    } else {
      unknownKey(estimator, key, "radius, directions, steps");
    }
  } else if (estimator == "bitmask-uniform") {
    applyBitmask(&s->bitmask_uniform, estimator, key, value, text);
  } else if (estimator == "bitmask-cosine") {
    applyBitmask(&s->bitmask_cosine, estimator, key, value, text);
  } else {
    throw Error("--setting: unknown estimator '" + estimator + "' in '" + text + "'");
  }
}

void validateSettings(const ScreenAoSettings& s) {
  validate(s.reference);
  validate(s.runtime);
  validate(s.hbao);
  validate(s.bitmask_uniform);
  validate(s.bitmask_cosine);
}

nlohmann::ordered_json settingsJson(const ScreenAoSettings& s, const std::string& estimator) {
  nlohmann::ordered_json j;
  if (estimator == "gtao-reference") {
    j = {{"radius", s.reference.radius},
         {"slices", s.reference.slices},
         {"refine_tolerance", s.reference.refine_tolerance},
         {"refine_levels", s.reference.refine_levels}};
  } else if (estimator == "gtao-runtime") {
    const GtaoRuntimeSettings& r = s.runtime;
    j = {{"radius", r.radius},
         {"directions", r.directions},
         {"steps", r.steps},
         {"thin_compensation", r.thin_compensation},
         {"intensity", r.intensity},
         {"temporal_blend", r.temporal_blend},
         {"frames", r.frames},
         {"blur", r.blur},
         {"falloff_range", kFalloffRange}};
  } else if (estimator == "hbao") {
    j = {{"radius", s.hbao.radius},
         {"directions", s.hbao.directions},
         {"steps", s.hbao.steps},
         {"seed", s.hbao.seed}};
  } else {
    const BitmaskSettings& b =
        estimator == "bitmask-uniform" ? s.bitmask_uniform : s.bitmask_cosine;
    j = {{"radius", b.radius},
         {"slices", b.slices},
         {"steps", b.steps},
         {"thickness", b.thickness},
         {"sectors", kSectors}};
  }
  return j;
}

double estimatorRadius(const ScreenAoSettings& s, const std::string& estimator) {
  return settingsJson(s, estimator).at("radius").get<double>();
}

AoEstimate runEstimator(const ScreenAoSettings& s, const std::string& estimator, const GBuffer& g) {
  if (estimator == "gtao-reference") return gtaoReference(g, s.reference);
  if (estimator == "gtao-runtime") return gtaoRuntime(g, s.runtime);
  if (estimator == "hbao") return hbao(g, s.hbao);
  if (estimator == "bitmask-uniform") return visibilityBitmask(g, s.bitmask_uniform);
  if (estimator == "bitmask-cosine") return visibilityBitmask(g, s.bitmask_cosine);
  throw Error("unknown estimator '" + estimator + "'");
}

}  // namespace gtbake
