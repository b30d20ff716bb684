#include "gtso/gtso_end_to_end.h"

#include <algorithm>
#include <cmath>

#include "common/progress.h"

namespace gtbake::gtso {
namespace {

using Json = nlohmann::json;

constexpr int kStressLobeDivisor = 4;  // the stress set has a quarter of the uniform lobes
// Seeds 1-3 chose the axis constants (bench_gtso_axes, docs/gtso.md §3); the report uses fresh
// seeds from 10.
constexpr std::uint64_t kFirstReportSeed = 10;
// The bars of docs/gtso.md §3a for what the runtime reads: uniform max, stress max (3D, 4D).
constexpr double kUniformBar[2] = {0.03, 0.06};
constexpr double kStressBar[2] = {0.05, 0.10};
constexpr double kRecommendRatio = 1.5;  // a format's error vs float32's for the recommendation

Json pointJson(const GtsoPoint& p) {
  return {{"A", p.A}, {"beta", p.beta}, {"r_p", p.r_p}, {"theta_o", p.thetaO}};
}

// Max / RMS of one format over the seeds: worst max, mean RMS, and their spread.
Json seedSummary(const std::vector<ErrorStats>& perSeed, std::uint64_t firstSeed) {
  Json seeds = Json::array();
  double maxMax = 0.0, minMax = HUGE_VAL, rmsSum = 0.0, minRms = HUGE_VAL, maxRms = 0.0;
  std::size_t worst = 0;
  for (std::size_t s = 0; s < perSeed.size(); ++s) {
    const ErrorStats& e = perSeed[s];
    seeds.push_back({{"seed", firstSeed + s}, {"max", e.max}, {"rms", e.rms}});
    if (e.max > maxMax) worst = s;
    maxMax = std::max(maxMax, e.max);
    minMax = std::min(minMax, e.max);
    rmsSum += e.rms;
    minRms = std::min(minRms, e.rms);
    maxRms = std::max(maxRms, e.rms);
  }
  return {{"max", maxMax},
          {"max_lowest_seed", minMax},
          {"rms", rmsSum / static_cast<double>(perSeed.size())},
          {"rms_lowest_seed", minRms},
          {"rms_highest_seed", maxRms},
          {"worst_point", pointJson(perSeed[worst].worst)},
          {"per_seed", seeds}};
}

// gtso.json end_to_end/points: the point sets and their distributions.
Json endToEndPointsJson(const GtsoOptions& o, int stressLobes, const std::string& exact) {
  return {
      {"uniform", o.error_lobes * kPointsPerLobe},
      {"stress", stressLobes * kPointsPerLobe},
      {"lobes_uniform", o.error_lobes},
      {"lobes_stress", stressLobes},
      {"points_per_lobe", kPointsPerLobe},
      {"seeds", o.error_seeds},
      {"first_seed", kFirstReportSeed},
      {"axis_selection_seeds", "1-3 (bench_gtso_axes)"},
      {"exact", exact},
      {"uniform_distribution",
       "per lobe r_p, cos theta_o uniform in [0, 1]; per point A uniform in [0, 1]; 4D cos beta "
       "uniform over the bent normals above the horizon; the 3D and 4D sets of a seed share their "
       "lobes (one integration per lobe)"},
      {"stress_distribution",
       "half the lobes grazing (cos theta_o in [0, 0.1]); alpha_v uniform within 6 alpha + 0.02 "
       "rad of the mirror step alpha_v = beta (3D: theta_o); 4D beta <= pi/2"}};
}

// gtso.json end_to_end/<3d|4d>: every format's errors over the seeds and the recommendation.
Json formatsJson(const std::vector<EncodedTable>& encoded,
                 const std::vector<std::vector<ErrorStats>>& uniform,
                 const std::vector<std::vector<ErrorStats>>& stress, int t) {
  Json formats;
  // Recommendation: the smallest format whose quantisation does not dominate: uniform max,
  // uniform RMS and stress max each within 1.5x those of the float32 table.
  const Json floatUniform = seedSummary(uniform[0], kFirstReportSeed);
  const Json floatStress = seedSummary(stress[0], kFirstReportSeed);
  std::size_t best = 0;
  for (std::size_t f = 0; f < encoded.size(); ++f) {
    const Json us = seedSummary(uniform[f], kFirstReportSeed);
    const Json ss = seedSummary(stress[f], kFirstReportSeed);
    formats[texelFormatName(encoded[f].format)] = {{"bytes", encoded[f].bytes.size()},
                                                   {"texel_max_error", encoded[f].texel_max},
                                                   {"texel_rms_error", encoded[f].texel_rms},
                                                   {"uniform", us},
                                                   {"stress", ss}};
    auto within = [](const Json& a, const Json& b, const char* k) {
      return a[k].get<double>() <= kRecommendRatio * b[k].get<double>();
    };
    const bool ok = within(us, floatUniform, "max") && within(us, floatUniform, "rms") &&
                    within(ss, floatStress, "max");
    if (ok && encoded[f].bytes.size() < encoded[best].bytes.size()) best = f;
  }
  return {{"formats", formats},
          {"recommended", texelFormatName(encoded[best].format)},
          {"bars", {{"uniform_max", kUniformBar[t]}, {"stress_max", kStressBar[t]}}}};
}

}  // namespace

EndToEnd measureEndToEnd(const Table& s3, const Table& s4, const GtsoOptions& o, int cells,
                         const std::string& exact) {
  EndToEnd out;
  const int stressLobes = std::max(1, o.error_lobes / kStressLobeDivisor);
  Json j;
  j["points"] = endToEndPointsJson(o, stressLobes, exact);
  Progress progress("gtso: end-to-end error", o.error_seeds, o.progress);
  std::vector<ErrorPointPair> uniformPoints, stressPoints;
  for (int s = 0; s < o.error_seeds; ++s) {
    const std::uint64_t seed = kFirstReportSeed + static_cast<std::uint64_t>(s);
    uniformPoints.push_back(
        makeErrorPointPair(PointSet::kUniform, o.error_lobes, kPointsPerLobe, seed, cells));
    stressPoints.push_back(
        makeErrorPointPair(PointSet::kStress, stressLobes, kPointsPerLobe, seed, cells));
    progress.add(1);
  }
  const Table* tables[2] = {&s3, &s4};
  for (int t = 0; t < 2; ++t) {
    const Table& table = *tables[t];
    const char* key = t == 0 ? "3d" : "4d";
    std::vector<EncodedTable> encoded;
    for (TexelFormat f : kEndToEndFormats) encoded.push_back(encodeTable(table, f));
    std::vector<std::vector<ErrorStats>> uniform(encoded.size()), stress(encoded.size());
    for (int s = 0; s < o.error_seeds; ++s) {
      const ErrorPoints& u = t == 0 ? uniformPoints[s].three : uniformPoints[s].four;
      const ErrorPoints& st = t == 0 ? stressPoints[s].three : stressPoints[s].four;
      for (std::size_t f = 0; f < encoded.size(); ++f) {
        uniform[f].push_back(lookupError(table, encoded[f], u));
        stress[f].push_back(lookupError(table, encoded[f], st));
      }
      if (t == 0 && s == 0) out.coneSamples = {u.points, u.exact};
      if (t == 0) {
        out.s3Points.push_back(u);
        out.s3Points.push_back(st);
        out.seeds.push_back(kFirstReportSeed + static_cast<std::uint64_t>(s));
      }
    }
    j[key] = formatsJson(encoded, uniform, stress, t);
  }
  j["recommendation_rule"] =
      "smallest format whose uniform max, uniform RMS and stress max are each within 1.5x those of "
      "the float32 table (quantisation does not dominate the interpolation error)";
  progress.finish();
  out.json = j;
  return out;
}

}  // namespace gtbake::gtso
