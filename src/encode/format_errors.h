// The end-to-end error of every texel format as shipped (docs/export.md §2b): the float32, BC4,
// R16 and R8 volumes of a table in its chosen layout, read through the shipped lookup (decode,
// half-texel remap, trilinear filter, 4D fold), against the exact S at fresh points over two
// seeds — the layout choice's report seed and the next one — and the format recommended per
// table. `gtbake gtso` measures only its float32 tables in table order; this is where the
// encoded formats are measured, on the bytes encode writes.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>

#include "encode/bc4_layout.h"

namespace gtbake {

// The second seed of the measurement (the first is the choice's report seed, kLayoutReportSeed).
inline constexpr std::uint64_t kFormatSecondSeed = kLayoutReportSeed + 1;

// encode.json end_to_end/<3d|4d> of one table (`c` chosen by chooseLayout for `t`); `progress`:
// a label for the exact-S bar of the second seed, nullptr silent.
nlohmann::json formatErrorsJson(const GtsoTable& t, const LayoutChoice& c,
                                const char* progress = nullptr);

// encode.json end_to_end: both tables, the points and the recommendation rule.
nlohmann::json endToEndJson(const GtsoInput& gtso, const GtsoLayouts& layouts, bool progress);

}  // namespace gtbake
