// The end-to-end error of `gtbake gtso` (docs/gtso.md §3a): |runtime lookup − exact S| of the
// float32 tables (interpolation and float rounding, no texel encoding: the encoded formats are
// measured by `gtbake encode` in their shipped layouts, docs/export.md §2b) at fresh uniform and
// stress points over several seeds; the points also feed the cone fit and the closed-form S3.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gtso/cone_fit.h"
#include "gtso/gtso_command.h"
#include "gtso/gtso_tables.h"

namespace gtbake::gtso {

inline constexpr int kStressLobeDivisor = 4;  // the stress set has a quarter of the uniform lobes

struct EndToEnd {
  nlohmann::json json;                // gtso.json end_to_end
  S3Samples coneSamples;              // the first seed's uniform 3D points with their exact S
  std::vector<ErrorPoints> s3Points;  // every seed's 3D uniform and stress points
  std::vector<std::uint64_t> seeds;
};

// Max / RMS of one table's errors over consecutive seeds from firstSeed: worst max, mean RMS,
// their spread over the seeds and the worst point (gtso.json and encode.json end_to_end).
nlohmann::json seedSummary(const std::vector<ErrorStats>& perSeed, std::uint64_t firstSeed);

// The measurement with o.error_lobes lobes per seed (stress: a quarter) and o.error_seeds seeds
// from 10 (seeds 1-3 chose the axis constants); `exact` describes the exact S in the JSON.
EndToEnd measureEndToEnd(const Table& s3, const Table& s4, const GtsoOptions& o, int cells,
                         const std::string& exact);

}  // namespace gtbake::gtso
