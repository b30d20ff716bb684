// Parsing of the command line's structured values, strict and with one-line errors.
#pragma once

#include <string>
#include <utility>

#include "fit/fit_command.h"

namespace gtbake {

// "WxH", e.g. "256x256", with up to six digits per side. Throws gtbake::Error otherwise; the
// sweep's own option check owns the allowed range.
std::pair<int, int> parseResolution(const std::string& text);

// "a1,a0,b1,b0,c1,c0": exactly six finite numbers. Throws gtbake::Error otherwise.
MultiBounceCoeffs parseCoeffs(const std::string& text);

}  // namespace gtbake
