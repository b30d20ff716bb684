// validate_data.json (validate_data.h): written by `gtbake fit`, read back by `validate --luts`.
// The header keys are indented; each view is one compact line (the file is data, ~1 MB).
#include <cmath>
#include <set>

#include "common/error.h"
#include "common/input_limits.h"
#include "fit/validate_data.h"

namespace gtbake {

namespace {

using nlohmann::json;
using nlohmann::ordered_json;

constexpr const char* kFormat = "gtbake validate data 1";
// Bounds of what the reader accepts (a hostile file cannot ask for more work than a real one).
constexpr int kMaxAlbedos = 64;
constexpr int kMaxBandSteps = 1000;  // a_steps (200 by default)
constexpr int kMaxRhoSteps = 200;    // rho_steps (80 by default)
constexpr int kMaxRanges = 10;
constexpr int kMaxDraws = 1'000'000;
// Points of all views together: 2^16 views of 8192² pixels (kMaxSweepViews, kMaxImageSide).
constexpr double kMaxPoints = 65536.0 * 8192.0 * 8192.0;

ordered_json coeffArray(const MultiBounceCoeffs& k) {
  ordered_json out = ordered_json::array();
  for (double v : k) out.push_back(v);
  return out;
}

ordered_json jackknifeJson(const SceneJackknife& jk) {
  ordered_json out = {{"unit", jk.unit}, {"available", jk.available}, {"message", jk.message}};
  out["threshold"] = jk.threshold;
  out["pointwise_threshold"] = jk.pointwise_threshold;
  out["pointwise_false_alarm"] = jk.pointwise_false_alarm;
  out["range_thresholds"] = jk.range_thresholds;
  out["monte_carlo_band_max"] = {
      {"value", jk.mc_band_max.value}, {"A", jk.mc_band_max.A}, {"rho", jk.mc_band_max.rho}};
  out["replicas"] = ordered_json::array();
  for (const LeaveOneOut& r : jk.leave_one_out) {
    out["replicas"].push_back({{"left_out", r.left_out}, {"linear", coeffArray(r.linear)}});
  }
  return out;
}

ordered_json viewJson(const ViewSums& v) {
  ordered_json out = {{"name", v.name}, {"scene", v.scene}, {"type", v.type}};
  out["weight_share"] = v.weight_share;
  out["floor_rmse"] = v.floor_rmse;
  out["bins"] = ordered_json::array();
  for (std::size_t b = 0; b < v.bins.size(); ++b) {
    if (v.bins[b].power[0] == 0.0) continue;  // an empty bin's sums are all zero
    out["bins"].push_back({{"bin", b}, {"power", v.bins[b].power}, {"albedo", v.bins[b].albedo}});
  }
  return out;
}

// --- reading -------------------------------------------------------------------------------

const json& member(const json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) throw Error(where + ": missing key \"" + key + "\"");
  return j.at(key);
}

double finite(const json& j, const std::string& where) {
  if (!j.is_number()) throw Error(where + ": not a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw Error(where + ": not finite");
  return v;
}

double finiteMember(const json& j, const char* key, const std::string& where) {
  return finite(member(j, key, where), where + " " + key);
}

const json& array(const json& j, std::size_t lo, std::size_t hi, const std::string& where) {
  if (!j.is_array() || j.size() < lo || j.size() > hi) {
    throw Error(where + ": expected an array of " + std::to_string(lo) + ".." + std::to_string(hi) +
                " entries");
  }
  return j;
}

template <std::size_t N>
std::array<double, N> fixedArray(const json& j, const std::string& where) {
  array(j, N, N, where);
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = finite(j[i], where);
  return out;
}

std::string name(const json& j, const char* key, const std::string& where) {
  const json& v = member(j, key, where);
  if (!v.is_string() || v.get<std::string>().empty() || v.get<std::string>().size() > 4096) {
    throw Error(where + ": \"" + key + "\" must be a non-empty string");
  }
  return v.get<std::string>();
}

BandRule bandRule(const json& j, const std::string& where) {
  BandRule rule;
  rule.a_steps = static_cast<int>(jsonInteger(j, "a_steps", 1, kMaxBandSteps, where));
  rule.rho_steps = static_cast<int>(jsonInteger(j, "rho_steps", 1, kMaxRhoSteps, where));
  rule.max_t.level = finiteMember(j, "level", where);
  rule.max_t.draws = static_cast<int>(jsonInteger(j, "draws", 1, kMaxDraws, where));
  rule.max_t.seed = static_cast<std::uint64_t>(jsonInteger(j, "seed", 0, INT64_MAX, where));
  const json& edges = array(member(j, "ranges", where), 2, kMaxRanges + 1, where + " ranges");
  rule.ranges.clear();
  for (const json& e : edges) rule.ranges.push_back(finite(e, where + " ranges"));
  if (!(rule.max_t.level > 0.0 && rule.max_t.level < 1.0)) throw Error(where + ": bad level");
  for (std::size_t r = 0; r < rule.ranges.size(); ++r) {
    const double bins = rule.ranges[r] * kValidateBins;
    const bool ordered = r == 0 ? rule.ranges[r] == 0.0 : rule.ranges[r] > rule.ranges[r - 1];
    if (!ordered || std::abs(bins - std::round(bins)) > 1e-9 || rule.ranges[r] > 1.0) {
      throw Error(where + ": ranges must rise from 0 to 1 on multiples of 0.05");
    }
  }
  if (rule.ranges.back() != 1.0) throw Error(where + ": ranges must end at 1");
  return rule;
}

SceneJackknife jackknife(const json& j, const BandRule& rule, const MultiBounceCoeffs& refit,
                         const std::vector<std::string>& groups, const std::string& where) {
  SceneJackknife jk;
  jk.rule = rule;
  jk.unit = name(j, "unit", where);
  const json& message = member(j, "message", where);
  if (!message.is_string()) throw Error(where + ": \"message\" must be a string");
  jk.message = message.get<std::string>();
  const json& mc = member(j, "monte_carlo_band_max", where);
  jk.mc_band_max = {finiteMember(mc, "value", where), finiteMember(mc, "A", where),
                    finiteMember(mc, "rho", where)};
  const json& replicas = array(member(j, "replicas", where), 0, groups.size(), where + " replicas");
  for (std::size_t r = 0; r < replicas.size(); ++r) {
    const std::string left_out = name(replicas[r], "left_out", where + " replica");
    if (left_out != groups[r]) {
      throw Error(where + ": replica " + std::to_string(r) + " leaves out '" + left_out +
                  "', but the views' " + jk.unit + " " + std::to_string(r) + " is '" + groups[r] +
                  "'");
    }
    const MultiBounceCoeffs k = fixedArray<6>(member(replicas[r], "linear", where), where);
    jk.leave_one_out.push_back({left_out, k, maxCurveDifference(k, refit), {}});
  }
  jk.scenes = groups.size();
  const json& available = member(j, "available", where);
  if (!available.is_boolean()) throw Error(where + ": \"available\" must be true or false");
  if (!available.get<bool>()) return jk;
  if (replicas.size() != groups.size() || groups.size() < kMinJackknifeScenes) {
    throw Error(where + ": an available jackknife needs one replica per " + jk.unit +
                " and at least " + std::to_string(kMinJackknifeScenes));
  }
  completeJackknife(jk);
  jk.threshold = finiteMember(j, "threshold", where);
  jk.pointwise_threshold = finiteMember(j, "pointwise_threshold", where);
  jk.pointwise_false_alarm = finiteMember(j, "pointwise_false_alarm", where);
  const json& thresholds = array(member(j, "range_thresholds", where), rule.ranges.size() - 1,
                                 rule.ranges.size() - 1, where + " range_thresholds");
  for (const json& t : thresholds) jk.range_thresholds.push_back(finite(t, where));
  return jk;
}

ViewSums view(const json& j, std::size_t albedos, const std::string& where) {
  ViewSums v;
  v.name = name(j, "name", where);
  v.scene = name(j, "scene", where);
  v.type = name(j, "type", where);
  v.weight_share = finiteMember(j, "weight_share", where);
  v.floor_rmse = finiteMember(j, "floor_rmse", where);
  v.bins.assign(kValidateBins, {{}, std::vector<std::array<double, kGSums>>(albedos)});
  std::set<long> seen;
  for (const json& bin : array(member(j, "bins", where), 0, kValidateBins, where + " bins")) {
    const long b = static_cast<long>(jsonInteger(bin, "bin", 0, kValidateBins - 1, where));
    if (!seen.insert(b).second) throw Error(where + ": bin " + std::to_string(b) + " twice");
    BinSums& out = v.bins[static_cast<std::size_t>(b)];
    out.power = fixedArray<kPowerSums>(member(bin, "power", where), where + " power");
    if (out.power[0] < 1.0 || out.power[0] > 9.0e15 || out.power[0] != std::floor(out.power[0])) {
      throw Error(where + ": a bin's point count must be a positive integer");
    }
    const json& g = array(member(bin, "albedo", where), albedos, albedos, where + " albedo");
    for (std::size_t a = 0; a < albedos; ++a) {
      out.albedo[a] = fixedArray<kGSums>(g[a], where + " albedo");
    }
  }
  return v;
}

void readSettings(const json& j, ValidateData& d, const std::string& where) {
  const json& s = member(j, "settings", where);
  d.settings.weighting = parseWeighting(name(s, "weighting", where));
  const json& open = member(s, "constrain_open", where);
  const json& eiv = member(s, "eiv_correction", where);
  if (!open.is_boolean() || !eiv.is_boolean()) throw Error(where + ": settings must be booleans");
  d.settings.constrain_open = open.get<bool>();
  d.settings.eiv_correction = eiv.get<bool>();
  d.input = name(j, "input", where);
  const json& sweep = member(j, "sweep", where);
  d.spp = static_cast<int>(jsonInteger(sweep, "spp", 1, kMaxSweepSpp, where));
  d.bounces = static_cast<int>(jsonInteger(sweep, "bounces", 1, kMaxSweepBounces, where));
  for (const json& rho : array(member(sweep, "albedos", where), 1, kMaxAlbedos, where)) {
    d.albedos.push_back(finite(rho, where + " albedos"));
    if (!(d.albedos.back() > 0.0 && d.albedos.back() <= 1.0)) {
      throw Error(where + ": an albedo must lie in (0, 1]");
    }
  }
}

}  // namespace

ordered_json validateDataJson(const ValidateData& d) {
  ordered_json out = {{"format", kFormat}};
  out["meaning"] =
      "what gtbake validate needs from this fit (docs/fit.md section 10): the refit, its Monte "
      "Carlo covariance, the leave-one-out refits with their simulated thresholds, the floor, "
      "and per view and bin of A (width 1/bins) the sums power[k] = sum A^k (k = 0..6) and, per "
      "albedo, sum G, sum G^2, sum G A, sum G A^2, sum G A^3";
  out["sweep"] = {{"spp", d.spp}, {"bounces", d.bounces}, {"albedos", d.albedos}};
  out["settings"] = {{"weighting", weightingName(d.settings.weighting)},
                     {"constrain_open", d.settings.constrain_open},
                     {"eiv_correction", d.settings.eiv_correction}};
  out["input"] = d.input;
  out["refit"] = coeffArray(d.refit);
  out["monte_carlo_se"] = coeffArray(d.mc_se);
  out["monte_carlo_covariance"] = d.mc_covariance;
  const BandRule& rule = d.scene_jackknife.rule;
  out["band_rule"] = {{"a_steps", rule.a_steps},   {"rho_steps", rule.rho_steps},
                      {"level", rule.max_t.level}, {"draws", rule.max_t.draws},
                      {"seed", rule.max_t.seed},   {"ranges", rule.ranges}};
  out["scene_jackknife"] = jackknifeJson(d.scene_jackknife);
  out["type_jackknife"] = jackknifeJson(d.type_jackknife);
  out["floor"] = {{"rmse", d.floor_rmse}, {"per_albedo", d.floor_per_albedo}};
  out["bins"] = kValidateBins;
  out["views"] = ordered_json::array();
  for (const ViewSums& v : d.views) out["views"].push_back(viewJson(v));
  return out;
}

std::string validateDataText(const ValidateData& d) {
  ordered_json j = validateDataJson(d);
  const ordered_json views = j["views"];
  j.erase("views");
  std::string text = j.dump(1);
  text.resize(text.size() - 2);  // the closing "\n}"
  text += ",\n \"views\": [";
  for (std::size_t v = 0; v < views.size(); ++v)
    text += (v == 0 ? "\n  " : ",\n  ") + views[v].dump();
  return text + "\n ]\n}\n";
}

ValidateData parseValidateData(const json& j, const std::string& where) {
  const json& format = member(j, "format", where);
  if (!format.is_string() || format.get<std::string>() != kFormat) {
    throw Error(where + ": not a gtbake validate data file (format \"" + kFormat + "\")");
  }
  if (jsonInteger(j, "bins", kValidateBins, kValidateBins, where) != kValidateBins) {
    throw Error(where + ": bins must be " + std::to_string(kValidateBins));
  }
  ValidateData d;
  readSettings(j, d, where);
  d.refit = fixedArray<6>(member(j, "refit", where), where + " refit");
  d.mc_se = fixedArray<6>(member(j, "monte_carlo_se", where), where + " monte_carlo_se");
  d.mc_covariance =
      fixedArray<36>(member(j, "monte_carlo_covariance", where), where + " covariance");
  const json& floor = member(j, "floor", where);
  d.floor_rmse = finiteMember(floor, "rmse", where + " floor");
  for (const json& f : array(member(floor, "per_albedo", where), d.albedos.size(), d.albedos.size(),
                             where + " floor per_albedo")) {
    d.floor_per_albedo.push_back(finite(f, where + " floor"));
  }
  std::set<std::string> names;
  double points = 0.0;
  for (const json& v :
       array(member(j, "views", where), 1, static_cast<std::size_t>(kMaxSweepViews), where)) {
    d.views.push_back(view(v, d.albedos.size(), where + " view"));
    if (!names.insert(d.views.back().name).second) {
      throw Error(where + ": two views are named '" + d.views.back().name + "'");
    }
    points += pointCount(d.views.back(), 0, kValidateBins);
  }
  if (points > kMaxPoints) throw Error(where + ": more points than any sweep holds");
  const BandRule rule = bandRule(member(j, "band_rule", where), where + " band_rule");
  d.scene_jackknife =
      jackknife(member(j, "scene_jackknife", where), rule, d.refit,
                groupViews(d.views, &ViewSums::scene).names, where + " scene_jackknife");
  d.type_jackknife =
      jackknife(member(j, "type_jackknife", where), rule, d.refit,
                groupViews(d.views, &ViewSums::type).names, where + " type_jackknife");
  return d;
}

}  // namespace gtbake
