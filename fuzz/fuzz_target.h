// The fuzz targets' shared interface: LLVMFuzzerTestOneInput (libFuzzer's entry point) and the
// valid inputs the deterministic mutation driver starts from.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace gtbake::fuzz {

// Valid inputs of the target (each mutated by the driver); also written as a libFuzzer corpus by
// `<driver> --write-corpus DIR`.
std::vector<std::string> seeds();

// A private scratch directory of this process, created on first use and removed at exit.
const std::string& scratchDir();

}  // namespace gtbake::fuzz
