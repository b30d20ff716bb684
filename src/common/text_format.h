// Numbers as text, one printf conversion at a time: the reports, summaries, channel names and
// JSON strings all format through here so a value reads the same wherever it is printed.
#pragma once

#include <string>
#include <vector>

namespace gtbake {

// `v` formatted by one printf conversion of a double (`format`, e.g. "%.4f", "%.9g", "%.1e").
std::string formatNumber(double v, const char* format = "%.4f");

// The values as "%.9g" numbers joined by commas (a list an option parses back exactly), or
// `empty` when there are none.
std::string formatNumberList(const std::vector<double>& values, const char* empty = "none");

}  // namespace gtbake
