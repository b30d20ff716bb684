// The generated verdict lines of docs/fit.md and docs/index.md: between the lines
// "<!-- shipped-verdict:begin -->" and "<!-- shipped-verdict:end -->" stands one line per range of
// A, "- A in [0.3, 0.7) (23.5 % of pixels): <text>", then "- overall: <headline>", from fit.json
// /shipped/verdict (the paper's constants by range of A, docs/fit.md §5). So the prose around it
// cannot claim a verdict the data do not give. Pure text in, text out; apps/gtbake-docs does the
// files.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace gtbake::docs {

// The block's lines for a fit.json document; gtbake::Error when it has no verdict by range.
std::string verdictLines(const nlohmann::json& fit);

// `text` with the block between "<!-- TAG:begin -->\n" and "<!-- TAG:end -->" set to `lines`, or
// nullopt when `text` has no (complete) block of that tag.
std::optional<std::string> withGeneratedBlock(const std::string& text, const std::string& tag,
                                              const std::string& lines);

}  // namespace gtbake::docs
