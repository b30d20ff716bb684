// The end-to-end error of `gtbake gtso` (docs/gtso.md §3a): |runtime lookup − exact S| of every
// texel format at fresh uniform and stress points over several seeds, and the format recommended
// per table; the points also feed the cone fit and the closed-form S3.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gtso/cone_fit.h"
#include "gtso/gtso_command.h"
#include "gtso/gtso_tables.h"

namespace gtbake::gtso {

inline constexpr TexelFormat kEndToEndFormats[] = {TexelFormat::kFloat32, TexelFormat::kBc4,
                                                   TexelFormat::kR16, TexelFormat::kR8};

struct EndToEnd {
  nlohmann::json json;                // gtso.json end_to_end
  S3Samples coneSamples;              // the first seed's uniform 3D points with their exact S
  std::vector<ErrorPoints> s3Points;  // every seed's 3D uniform and stress points
  std::vector<std::uint64_t> seeds;
};

// The measurement with o.error_lobes lobes per seed (stress: a quarter) and o.error_seeds seeds
// from 10 (seeds 1-3 chose the axis constants); `exact` describes the exact S in the JSON.
EndToEnd measureEndToEnd(const Table& s3, const Table& s4, const GtsoOptions& o, int cells,
                         const std::string& exact);

}  // namespace gtbake::gtso
