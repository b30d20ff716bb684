// Overflow-checked size arithmetic for every size that comes from a file (glTF accessors and
// buffer views, EXR windows, table dims in gtso.json, counts in sweep.json and fit.json). A size
// that does not fit is a malformed input, reported as a gtbake::Error naming `what`.
#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include "common/error.h"

namespace gtbake {

inline std::uint64_t checkedAdd(std::uint64_t a, std::uint64_t b, const std::string& what) {
  std::uint64_t sum = 0;
  if (__builtin_add_overflow(a, b, &sum)) throw Error(what + ": size overflows 64 bits");
  return sum;
}

inline std::uint64_t checkedMul(std::uint64_t a, std::uint64_t b, const std::string& what) {
  std::uint64_t product = 0;
  if (__builtin_mul_overflow(a, b, &product)) throw Error(what + ": size overflows 64 bits");
  return product;
}

}  // namespace gtbake
