#include "sweep/sweep_set.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "common/error.h"
#include "common/input_limits.h"
#include "common/text_format.h"

namespace gtbake {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string requireString(const json& object, const char* key, const std::string& where) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_string() || it->get<std::string>().empty()) {
    throw Error(where + ": '" + key + "' must be a non-empty string");
  }
  return it->get<std::string>();
}

// An optional string member: `fallback` when absent, else a non-empty string.
std::string optionalString(const json& object, const char* key, const std::string& fallback,
                           const std::string& where) {
  return object.contains(key) ? requireString(object, key, where) : fallback;
}

int imageSide(const json& object, const char* key, const std::string& where) {
  return static_cast<int>(jsonInteger(object, key, 1, kMaxImageSide, where));
}

// A list of parameters that name channels by hundredths (the G### albedos, the S### roughness):
// each a number in [lo, hi] (lo exclusive when `open_low`) with a channel name of its own, and,
// when `exact`, a hundredth exactly (the albedos: the G### value is the albedo fitted), so that a
// nudged or repeated list cannot describe channels the sweep never traced. Empty when absent.
std::vector<double> hundredthsList(const json& settings, const char* key, double lo, bool open_low,
                                   bool exact, const std::string& where) {
  const double hi = 1.0;
  std::vector<double> out;
  if (!settings.contains(key) || settings[key].is_null()) return out;
  const json& list = settings[key];
  if (!list.is_array()) throw Error(where + ": settings '" + key + "' must be an array");
  std::set<long> seen;
  for (const json& v : list) {
    const double x = v.is_number() ? v.get<double>() : NAN;
    if (!(open_low ? x > lo : x >= lo) || !(x <= hi)) {
      throw Error(where + ": every value of settings '" + key + "' must be a number in " +
                  (open_low ? "(" : "[") + formatNumber(lo, "%g") + ", " + formatNumber(hi, "%g") +
                  "], got " + list.dump());
    }
    if ((exact && std::round(x * 100.0) / 100.0 != x) ||
        !seen.insert(std::lround(x * 100.0)).second) {
      throw Error(where + ": " + key + " must be distinct hundredths (their channel names), got " +
                  list.dump());
    }
    out.push_back(x);
  }
  return out;
}

std::vector<double> gbufferRadii(const json& settings, const std::string& where) {
  std::vector<double> out;
  if (!settings.contains("gbuffer_radii") || settings["gbuffer_radii"].is_null()) return out;
  const json& list = settings["gbuffer_radii"];
  if (!list.is_array()) throw Error(where + ": settings 'gbuffer_radii' must be an array");
  for (const json& v : list) {
    const double r = v.is_number() ? v.get<double>() : NAN;
    if (!(r > 0.0 && std::isfinite(r)) || (!out.empty() && !(r > out.back()))) {
      throw Error(where + ": settings 'gbuffer_radii' must be ascending positive metres, got " +
                  list.dump());
    }
    out.push_back(r);
  }
  return out;
}

SweepSettings readSettings(const json& doc, const std::string& where) {
  if (!doc.is_object() || !doc.contains("settings") || !doc["settings"].is_object()) {
    throw Error(where + ": missing 'settings' object");
  }
  const json& s = doc["settings"];
  const std::string at = where + " settings";
  SweepSettings out;
  out.spp = static_cast<int>(jsonInteger(s, "spp", 2, kMaxSweepSpp, at));
  out.bounces = static_cast<int>(jsonInteger(s, "bounces", 1, kMaxSweepBounces, at));
  out.width = s.contains("width") ? imageSide(s, "width", at) : 0;
  out.height = s.contains("height") ? imageSide(s, "height", at) : 0;
  if (s.contains("radius") && !s["radius"].is_null()) {
    const double r = s["radius"].is_number() ? s["radius"].get<double>() : NAN;
    if (!(r > 0.0)) throw Error(at + ": 'radius' must be positive metres or null");
    out.radius = r;
  }
  if (s.contains("seed")) {
    out.seed = static_cast<std::uint64_t>(jsonInteger(s, "seed", 0, INT64_MAX, at));
  }
  out.albedos = hundredthsList(s, "albedos", 0.0, true, true, where);
  out.specular_roughness = hundredthsList(s, "specular_roughness", 0.0, false, false, where);
  if (!out.specular_roughness.empty()) {
    out.specular_spp =
        static_cast<int>(jsonInteger(s, "specular_spp", 2, kMaxSweepSpecularSpp, at));
  }
  out.gbuffer_radii = gbufferRadii(s, where);
  if (s.contains("transfer")) {
    if (!s["transfer"].is_boolean()) throw Error(at + ": 'transfer' must be true or false");
    out.transfer = s["transfer"].get<bool>();
  }
  return out;
}

SweepView readView(const fs::path& dir, const json& entry, const SweepSettings& settings,
                   const std::string& where) {
  SweepView v;
  v.name = requireString(entry, "name", where + " view");
  const std::string at = where + " view " + v.name;
  v.scene = optionalString(entry, "scene", v.name, at);
  v.type = optionalString(entry, "type", v.scene, at);
  v.file = requireString(entry, "file", at);
  fileInsideDirectory(dir, v.file, at);
  v.gltf = entry.contains("gltf") ? requireString(entry, "gltf", at) : std::string();
  if (entry.contains("width") || settings.width == 0) {
    v.width = imageSide(entry, "width", at);
    v.height = imageSide(entry, "height", at);
  } else {
    v.width = settings.width;
    v.height = settings.height == 0 ? settings.width : settings.height;
  }
  if (entry.contains("unmasked_pixels")) {
    v.unmasked_pixels =
        jsonInteger(entry, "unmasked_pixels", 0, static_cast<std::int64_t>(v.width) * v.height, at);
  }
  v.camera = entry.contains("camera") ? entry["camera"] : json();
  return v;
}

// Each view's name and each file (lexically normalised) once: a view's outputs are named after
// it, and one image read twice would count twice.
void requireDistinct(const std::vector<SweepView>& views, const std::string& where) {
  std::set<std::string> names, files;
  for (const SweepView& v : views) {
    if (!names.insert(v.name).second ||
        !files.insert(fs::path(v.file).lexically_normal().string()).second) {
      throw Error(where + ": view '" + v.name + "' (" + v.file + ") is listed twice");
    }
  }
}

}  // namespace

SweepSet readSweepSet(const fs::path& dir) {
  if (fs::exists(dir) && !fs::is_directory(dir)) {
    throw Error("--sweep " + dir.string() + " is a file; pass the directory `gtbake sweep` wrote");
  }
  if (!fs::is_directory(dir)) throw Error("sweep directory " + dir.string() + " does not exist");
  if (!fs::is_regular_file(dir / "sweep.json")) {
    throw Error(dir.string() + " is not a sweep directory (no sweep.json); run `gtbake sweep`");
  }
  SweepSet set;
  set.dir = dir;
  set.where = (dir / "sweep.json").string();
  set.manifest = readOutputSet(dir, "sweep");
  const json doc = parseJsonText(set.manifest.readVerified("sweep.json"), set.where);
  set.settings = readSettings(doc, set.where);
  if (doc.contains("gtbake_version") && doc["gtbake_version"].is_string()) {
    set.version = doc["gtbake_version"].get<std::string>();
  }
  if (doc.contains("scenes")) {
    throw Error(set.where + " lists its views as 'scenes', an older layout that this gtbake " +
                "does not read: re-run `gtbake sweep` to write it with 'views'");
  }
  if (!doc.contains("views") || !doc["views"].is_array() || doc["views"].empty()) {
    throw Error(set.where + ": 'views' must be a non-empty array");
  }
  if (doc["views"].size() > static_cast<std::size_t>(kMaxSweepViews)) {
    throw Error(set.where + ": more than " + std::to_string(kMaxSweepViews) + " views");
  }
  for (const json& entry : doc["views"]) {
    if (!entry.is_object()) throw Error(set.where + ": every views[] entry must be an object");
    set.views.push_back(readView(dir, entry, set.settings, set.where));
  }
  requireDistinct(set.views, set.where);
  return set;
}

std::string nearFieldSuffix(double radius) {
  std::string suffix = "_R" + formatNumber(radius, "%g");
  std::replace(suffix.begin(), suffix.end(), '.', 'p');
  return suffix;
}

namespace {

// `prefix` and the value in hundredths, three digits ("G050" for 0.5).
std::string hundredthsChannelName(char prefix, double value) {
  return prefix + formatNumber(std::round(value * 100.0), "%03.0f");
}

}  // namespace

std::string albedoChannelName(double albedo) {
  return hundredthsChannelName('G', albedo);
}

std::string nearFieldChannelName(const std::string& name, double radius) {
  return name + nearFieldSuffix(radius);
}

std::string gbufferRadiusChannelName(double radius) {
  return nearFieldChannelName("A", radius);
}

std::string specularChannelName(double roughness) {
  return hundredthsChannelName('S', roughness);
}

std::string transferChannelName(int k, int i) {
  return "T" + std::to_string(k) + "_SH" + std::to_string(i);
}

std::string truthChannelSuffix(const SweepSet& set, std::optional<double> radius) {
  if (!radius) return "";
  for (double r : set.settings.gbuffer_radii) {
    if (nearFieldSuffix(r) == nearFieldSuffix(*radius)) return nearFieldSuffix(*radius);
  }
  throw Error(set.where + ": no near-field truth at radius " + formatNumber(*radius, "%g") +
              " m; the sweep holds gbuffer_radii " +
              formatNumberList(set.settings.gbuffer_radii, "none") +
              " (trace it with `gtbake sweep --gbuffer-radius`)");
}

}  // namespace gtbake
