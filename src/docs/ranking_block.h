// The generated ranking list of docs/validate_gtso.md §2: between the lines
// "<!-- ranking-tests:begin -->" and "<!-- ranking-tests:end -->" stands one line per roughness,
// "- r_p 0.25: <statement>", the statements of validate_gtso.json
// /ranking_tests/by_roughness/S<r_p*100>/statement (built from /best and the paired scene-level
// tests) in the sweep's roughness order. Pure text in, text out; apps/gtbake-docs does the files.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace gtbake::docs {

// The block's lines for a validate_gtso.json document; gtbake::Error when it has no ranking tests.
std::string rankingLines(const nlohmann::json& validate_gtso);

// `text` with its ranking block set to `lines`, or nullopt when `text` has no (complete) block.
std::optional<std::string> withRankingBlock(const std::string& text, const std::string& lines);

}  // namespace gtbake::docs
