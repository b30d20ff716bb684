// Parsing of the command line's structured values, strict and with one-line errors.
#pragma once

#include <string>
#include <utility>

#include "fit/fit_command.h"

namespace gtbake {

// "WxH" with 1 ≤ W, H ≤ 8192, e.g. "256x256". Throws gtbake::Error otherwise.
std::pair<int, int> parseResolution(const std::string& text);

// "a1,a0,b1,b0,c1,c0": exactly six finite numbers. Throws gtbake::Error otherwise.
MultiBounceCoeffs parseCoeffs(const std::string& text);

}  // namespace gtbake
