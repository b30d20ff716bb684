// What validate-gtso computes before it formats anything (docs/validate_gtso.md): the samples,
// every method's values, the u fits, the tabulated errors and the scene-level statistics, each
// part under its own progress bar and timed (validate_gtso.json /timings/parts).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "validate_gtso/cone_u_fit.h"
#include "validate_gtso/gtso_lookup.h"
#include "validate_gtso/scene_statistics.h"
#include "validate_gtso/specular_methods.h"
#include "validate_gtso/specular_sweep.h"
#include "validate_gtso/validate_gtso_command.h"

namespace gtbake {

// Bins of the angle between b and the plane of n and ωr (degrees) for the 4D table's error.
inline constexpr double kPlaneBins[] = {0.0, 2.0, 5.0, 10.0, 20.0, 90.0};
inline constexpr int kPlaneBinCount = 5;
// The texel formats beside the float table they encode: what a format costs at real pixels.
inline constexpr std::pair<Method, Method> kFormatMethods[] = {
    {Method::kS3Bc4, Method::kS3Float}, {Method::kS3R16, Method::kS3Float},
    {Method::kS3R8, Method::kS3Float},  {Method::kS4Bc4, Method::kS4Float},
    {Method::kS4R16, Method::kS4Float}, {Method::kS4R8, Method::kS4Float}};
inline constexpr int kFormatMethodCount = 6;

// Error statistics of every method: per scene × roughness, per roughness, overall; and the 4D/3D
// tables' errors by the out-of-plane angle of b.
struct Tables {
  // [method][scene][roughness]
  std::vector<std::vector<std::vector<ErrorStats>>> cell;
  std::vector<std::vector<ErrorStats>> per_roughness;           // [method][roughness]
  std::vector<ErrorStats> overall;                              // [method]
  std::array<std::array<ErrorStats, kPlaneBinCount>, 2> plane;  // S4_bc4, S3_bc4
  std::array<ErrorStats, kFormatMethodCount> vs_float;          // kFormatMethods: format − float
};

// What validate-gtso computes before it formats anything: the samples, every method's values,
// the u fits and the tabulated errors.
struct Analysis {
  // Empty: the ray-traced A and b of the sweep; else the screen-space estimator whose Â and b̂
  // replaced them (no u fit, no floor: docs/validate_gtso.md §6).
  std::string estimator;
  bool rayTraced() const { return estimator.empty(); }
  double shipped_u = 0.0;  // on an estimator's inputs: the ray-traced run's u, scored as fitted
  SpecularSweep sweep;
  TablesLookupInfo tables;
  std::vector<SpecularSample> samples;
  UFits spec, perceptual;
  std::vector<std::vector<float>> values;
  std::vector<Method> methods;
  Tables t;  // against the sweep's truth at the estimator's radius (near-field), else unbounded
  // With a near-field truth: the same values against the unbounded S (docs/validate_gtso.md §6).
  std::optional<Tables> unbounded;
  std::vector<std::vector<Method>> ranking;
  SceneStatistics
      scene_stats;  // scene-level u interval, paired rankings, floor (scene_statistics.h)
  std::vector<std::pair<std::string, double>> part_seconds;  // each part's wall time, in order
};

Analysis analyse(const ValidateGtsoOptions& options);

}  // namespace gtbake
