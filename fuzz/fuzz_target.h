// The fuzz targets' shared interface: LLVMFuzzerTestOneInput (libFuzzer's entry point) and the
// valid inputs the deterministic mutation driver starts from.
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <utility>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace gtbake::fuzz {

// Valid inputs of the target (each mutated by the driver); also written as a libFuzzer corpus by
// `<driver> --write-corpus DIR`.
std::vector<std::string> seeds();

// A private scratch directory of this process, created on first use and removed at exit.
const std::string& scratchDir();

// Aborts, as a crash would, when an error's message is not one line (every refusal is one line
// on stderr, docs/limits.md): the later readers' targets check it.
void requireOneLine(const std::exception& e);

// Writes `files` (name, bytes) into `dir` (created if needed) and <command>.manifest.json listing
// them as an output set records them (names, sizes, SHA-256), so a reader's own checks run on
// the bytes. Unlike sealOutputSet it neither stages nor syncs: a loop seals thousands of times.
void writeSet(const std::string& dir, const std::string& command,
              const std::vector<std::pair<std::string, std::string>>& files);

}  // namespace gtbake::fuzz
