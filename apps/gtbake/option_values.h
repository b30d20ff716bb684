// Parsing of the command line's structured values, strict and with one-line errors: every
// text-to-value conversion of apps/gtbake beyond CLI11's numbers (the libraries take values).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "fit/fit_command.h"

namespace gtbake {

// "WxH", e.g. "256x256", with up to six digits per side. Throws gtbake::Error otherwise; the
// sweep's own option check owns the allowed range.
std::pair<int, int> parseResolution(const std::string& text);

// "a1,a0,b1,b0,c1,c0": exactly six finite numbers. Throws gtbake::Error naming `option`
// otherwise (an empty text is an error, not the default constants).
MultiBounceCoeffs parseCoeffs(const std::string& text, const std::string& option = "--coeffs");

// A seed: decimal digits only, 0 ≤ seed < 2^64 ("-1" and "18446744073709551616" are errors, not
// silently wrapped). Throws gtbake::Error naming `option`.
std::uint64_t parseSeed(const std::string& text, const std::string& option);

// --shard "I/N" with 0 ≤ I < N ≤ kMaxShards → (I, N); a one-line gtbake::Error otherwise.
std::pair<int, int> parseShard(const std::string& text);

// --gbuffer-radius: "none" (empty) or comma-separated positive finite metres. Throws gtbake::Error.
std::vector<double> parseGbufferRadii(const std::string& text);

// --specular-roughness: "none" (empty) or comma-separated r_p values. Throws gtbake::Error.
std::vector<double> parseSpecularRoughness(const std::string& text);

// --estimator NAME [--screen-ao DIR] of fit and validate: the A a profile is fitted on
// (docs/profiles.md). An empty name is the ray-traced A (then --screen-ao must be empty too); a
// name must be a `gtbake screen-ao` estimator, built-in or imported (isEstimatorName; the set
// itself says whether it holds it); DIR defaults to <sweep>/screen_ao, where `gtbake all` writes
// it; truth is --truth, near or unbounded. Throws gtbake::Error.
AoInput parseAoInput(const std::string& estimator, const std::string& screen_ao,
                     const std::string& truth, const std::filesystem::path& sweep);

}  // namespace gtbake
