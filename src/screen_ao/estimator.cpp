#include "screen_ao/estimator.h"

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

// The setting's error for a key the estimator lacks.
[[noreturn]] void unknownKey(const std::string& text, const std::string& key) {
  const std::string name = text.substr(0, text.find('.'));
  throw Error("--setting: " + name + " has no setting '" + key + "' (it has " +
              describe(name, "--setting").keys + ")");
}

void applyReference(ScreenAoSettings* s, const std::string& key, const std::string& value,
                    const std::string& text) {
  GtaoReferenceSettings& r = s->reference;
  if (key == "radius") {
    r.radius = parseNumber(value, text);
  } else if (key == "slices") {
    r.slices = parseInteger(value, text);
  } else if (key == "refine_tolerance") {
    r.refine_tolerance = parseNumber(value, text);
  } else if (key == "refine_levels") {
    r.refine_levels = parseInteger(value, text);
  } else {
    unknownKey(text, key);
  }
}

void applyRuntime(ScreenAoSettings* s, const std::string& key, const std::string& value,
                  const std::string& text) {
  GtaoRuntimeSettings& r = s->runtime;
  if (key == "radius") {
    r.radius = parseNumber(value, text);
  } else if (key == "directions") {
    r.directions = parseInteger(value, text);
  } else if (key == "steps") {
    r.steps = parseInteger(value, text);
  } else if (key == "thin_compensation") {
    r.thin_compensation = parseNumber(value, text);
  } else if (key == "intensity") {
    r.intensity = parseNumber(value, text);
  } else if (key == "temporal_blend") {
    r.temporal_blend = parseNumber(value, text);
  } else if (key == "frames") {
    r.frames = parseInteger(value, text);
  } else if (key == "blur") {
    if (value != "0" && value != "1") throw Error("--setting " + text + ": blur is 0 or 1");
    r.blur = value == "1";
  } else {
    unknownKey(text, key);
  }
}

void applyHbao(ScreenAoSettings* s, const std::string& key, const std::string& value,
               const std::string& text) {
  if (key == "radius") {
    s->hbao.radius = parseNumber(value, text);
  } else if (key == "directions") {
    s->hbao.directions = parseInteger(value, text);
  } else if (key == "steps") {
    s->hbao.steps = parseInteger(value, text);
  } else {
    unknownKey(text, key);
  }
}

template <BitmaskSettings ScreenAoSettings::*member>
void applyBitmask(ScreenAoSettings* s, const std::string& key, const std::string& value,
                  const std::string& text) {
  BitmaskSettings& b = s->*member;
  if (key == "radius") {
    b.radius = parseNumber(value, text);
  } else if (key == "slices") {
    b.slices = parseInteger(value, text);
  } else if (key == "steps") {
    b.steps = parseInteger(value, text);
  } else if (key == "thickness") {
    b.thickness = parseNumber(value, text);
  } else {
    unknownKey(text, key);
  }
}

nlohmann::ordered_json referenceJson(const ScreenAoSettings& s) {
  return {{"radius", s.reference.radius},
          {"slices", s.reference.slices},
          {"refine_tolerance", s.reference.refine_tolerance},
          {"refine_levels", s.reference.refine_levels}};
}

nlohmann::ordered_json runtimeJson(const ScreenAoSettings& s) {
  const GtaoRuntimeSettings& r = s.runtime;
  return {{"radius", r.radius},
          {"directions", r.directions},
          {"steps", r.steps},
          {"thin_compensation", r.thin_compensation},
          {"intensity", r.intensity},
          {"temporal_blend", r.temporal_blend},
          {"frames", r.frames},
          {"blur", r.blur},
          {"falloff_range", kFalloffRange}};
}

nlohmann::ordered_json hbaoJson(const ScreenAoSettings& s) {
  return {{"radius", s.hbao.radius},
          {"directions", s.hbao.directions},
          {"steps", s.hbao.steps},
          {"seed", s.hbao.seed}};
}

template <BitmaskSettings ScreenAoSettings::*member>
nlohmann::ordered_json bitmaskJson(const ScreenAoSettings& s) {
  const BitmaskSettings& b = s.*member;
  return {{"radius", b.radius},
          {"slices", b.slices},
          {"steps", b.steps},
          {"thickness", b.thickness},
          {"sectors", kSectors}};
}

template <BitmaskSettings ScreenAoSettings::*member>
AoEstimate runBitmask(const ScreenAoSettings& s, const GBuffer& g) {
  return visibilityBitmask(g, s.*member);
}

// The runtime pass's searched settings (docs/tune.md §1): factors of two for the lengths and the
// exponent (each value is a full run of the pass; the optimum is refined by the parabola, §3).
std::vector<TunedKey> runtimeTuned() {
  return {{"radius",
           [](ScreenAoSettings& s) -> double& { return s.runtime.radius; },
           true,
           {0.5, 1.0, 2.0, 4.0},
           {0.0625, "search floor: 1/16 m, three halvings below the 0.5 m grid start"},
           {4.0, "screen-space maximum: 4 m, past it the horizon search leaves the view"}},
          {"intensity",
           [](ScreenAoSettings& s) -> double& { return s.runtime.intensity; },
           true,
           {0.5, 1.0, 2.0, 4.0, 8.0},
           {0.25, "search floor: A^0.25, the pass's occlusion all but erased"},
           {16.0, "the pass's range: intensity <= 16 (docs/screen_ao.md)"}},
          {"thin_compensation",
           [](ScreenAoSettings& s) -> double& { return s.runtime.thin_compensation; },
           false,
           {0.0, 0.5, 1.0},
           {0.0, "physical: thin compensation >= 0 (0 is off)"},
           {10.0, "the pass's range: thin_compensation <= 10 (docs/screen_ao.md)"}}};
}

// A bitmask estimator's searched setting, on its own settings `member`.
template <BitmaskSettings ScreenAoSettings::*member>
std::vector<TunedKey> bitmaskTuned() {
  return {{"thickness",
           [](ScreenAoSettings& s) -> double& { return (s.*member).thickness; },
           true,
           {0.125, 0.25, 0.5, 1.0, 2.0, 4.0},
           {0.03125, "search floor: 1/32 m, two halvings below the 0.125 m grid start"},
           {8.0, "physical: 8 radii, a slab that thick is an infinite one to 1 of 32 sectors"}}};
}

}  // namespace

const std::array<EstimatorDescriptor, 5>& estimatorDescriptors() {
  static const std::array<EstimatorDescriptor, 5> table = {{
      {Estimator::kGtaoReference,
       "gtao-reference",
       "radius, slices, refine_tolerance, refine_levels",
       applyReference,
       referenceJson,
       [](const ScreenAoSettings& s, const GBuffer& g) { return gtaoReference(g, s.reference); },
       nullptr,
       {}},
      {Estimator::kGtaoRuntime, "gtao-runtime",
       "radius, directions, steps, thin_compensation, intensity, temporal_blend, frames, blur",
       applyRuntime, runtimeJson,
       [](const ScreenAoSettings& s, const GBuffer& g) { return gtaoRuntime(g, s.runtime); },
       nullptr, runtimeTuned()},
      {Estimator::kHbao,
       "hbao",
       "radius, directions, steps",
       applyHbao,
       hbaoJson,
       [](const ScreenAoSettings& s, const GBuffer& g) { return hbao(g, s.hbao); },
       nullptr,
       {}},
      {Estimator::kBitmaskUniform, "bitmask-uniform", "radius, slices, steps, thickness",
       applyBitmask<&ScreenAoSettings::bitmask_uniform>,
       bitmaskJson<&ScreenAoSettings::bitmask_uniform>,
       runBitmask<&ScreenAoSettings::bitmask_uniform>, &ScreenAoSettings::bitmask_uniform,
       bitmaskTuned<&ScreenAoSettings::bitmask_uniform>()},
      {Estimator::kBitmaskCosine, "bitmask-cosine", "radius, slices, steps, thickness",
       applyBitmask<&ScreenAoSettings::bitmask_cosine>,
       bitmaskJson<&ScreenAoSettings::bitmask_cosine>,
       runBitmask<&ScreenAoSettings::bitmask_cosine>, &ScreenAoSettings::bitmask_cosine,
       bitmaskTuned<&ScreenAoSettings::bitmask_cosine>()},
  }};
  return table;
}

const EstimatorDescriptor& describe(Estimator e) {
  return estimatorDescriptors()[static_cast<std::size_t>(e)];
}

std::optional<Estimator> findEstimator(const std::string& name) {
  for (const EstimatorDescriptor& d : estimatorDescriptors()) {
    if (name == d.name) return d.id;
  }
  return std::nullopt;
}

const EstimatorDescriptor& describe(const std::string& name, const std::string& what) {
  const std::optional<Estimator> e = findEstimator(name);
  if (!e) {
    std::string known;
    for (const EstimatorDescriptor& d : estimatorDescriptors()) {
      known += (known.empty() ? "" : ", ") + std::string(d.name);
    }
    throw Error(what + ": unknown estimator '" + name + "' (known: " + known + ")");
  }
  return describe(*e);
}

}  // namespace gtbake
