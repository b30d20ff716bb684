#include "gtso/gtso_end_to_end.h"

#include <algorithm>
#include <cmath>

#include "common/progress.h"

namespace gtbake::gtso {
namespace {

using Json = nlohmann::json;

// Seeds 1-3 chose the axis constants (bench_gtso_axes, docs/gtso.md §3); the report uses fresh
// seeds from 10.
constexpr std::uint64_t kFirstReportSeed = 10;

Json pointJson(const GtsoPoint& p) {
  return {{"A", p.A}, {"beta", p.beta}, {"r_p", p.r_p}, {"theta_o", p.theta_o}};
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

// gtso.json end_to_end/<3d|4d>: the float32 table's errors over the seeds.
Json formatsJson(const EncodedTable& floats, const std::vector<ErrorStats>& uniform,
                 const std::vector<ErrorStats>& stress) {
  Json formats;
  formats["float32"] = {{"bytes", floats.bytes.size()},
                        {"texel_max_error", floats.texel_max},
                        {"texel_rms_error", floats.texel_rms},
                        {"uniform", seedSummary(uniform, kFirstReportSeed)},
                        {"stress", seedSummary(stress, kFirstReportSeed)}};
  return {{"formats", formats}};
}

}  // namespace

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
    const EncodedTable floats = floatTable(table);
    std::vector<ErrorStats> uniform, stress;
    for (int s = 0; s < o.error_seeds; ++s) {
      const ErrorPoints& u = t == 0 ? uniformPoints[s].three : uniformPoints[s].four;
      const ErrorPoints& st = t == 0 ? stressPoints[s].three : stressPoints[s].four;
      uniform.push_back(lookupError(table, floats, u));
      stress.push_back(lookupError(table, floats, st));
      if (t == 0 && s == 0) out.coneSamples = {u.points, u.exact};
      if (t == 0) {
        out.s3Points.push_back(u);
        out.s3Points.push_back(st);
        out.seeds.push_back(kFirstReportSeed + static_cast<std::uint64_t>(s));
      }
    }
    j[key] = formatsJson(floats, uniform, stress);
  }
  j["encoded_formats"] =
      "BC4, R16 and R8 are measured by gtbake encode in their shipped layouts (encode.json "
      "end_to_end), which also recommends one";
  progress.finish();
  out.json = j;
  return out;
}

}  // namespace gtbake::gtso
