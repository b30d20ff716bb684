// Mathematical constants, one definition each for every stage (C++17 has no std::numbers).
#pragma once

namespace gtbake {

// π rounded to the nearest double (bit-identical to std::acos(-1.0) on IEEE-754 targets).
inline constexpr double kPi = 3.14159265358979323846;

}  // namespace gtbake
