// Bounds on the work and memory an input may ask for, and the checked readers every stage uses
// for files it did not write itself in this run (docs/limits.md lists them all).
//
// Each limit has a default that covers every scene and table gtbake is meant for with a wide
// margin, and an environment variable that raises it; an error names both, e.g.
// "scene.gltf: 2.1e+08 triangles exceed the limit of 5e+07 (set GTBAKE_MAX_TRIANGLES to raise it)".
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace gtbake {

struct Limit {
  const char* env;         // environment variable that overrides the default
  std::uint64_t fallback;  // default value
  const char* unit;        // what is counted ("triangles", "bytes", ...)
  // The most the code survives: the variable cannot raise the limit past it (docs/limits.md
  // "Bounded work and memory").
  std::uint64_t ceiling = UINT64_MAX;
};

// clang-format off
inline constexpr Limit kMaxTriangles   {"GTBAKE_MAX_TRIANGLES",   50'000'000, "triangles"};
inline constexpr Limit kMaxVertices    {"GTBAKE_MAX_VERTICES",    50'000'000, "vertices"};
inline constexpr Limit kMaxInstances   {"GTBAKE_MAX_INSTANCES",    1'000'000, "node instances"};
inline constexpr Limit kMaxInputBytes  {"GTBAKE_MAX_INPUT_BYTES", 4'000'000'000, "bytes"};
// Parsing, copying and printing JSON recurse once per level: 3,000 levels overflow an 8 MB stack
// under ASan (1,000 do not) and 100,000 without it, so the depth cannot be raised past 1,000.
inline constexpr Limit kMaxJsonDepth   {"GTBAKE_MAX_JSON_DEPTH",         64, "levels of JSON nesting", 1000};
// clang-format on

// Fixed bounds of a sweep: what `gtbake sweep` accepts on its command line and what every reader
// of a sweep's files checks again (docs/limits.md "Bounded work and memory").
inline constexpr int kMaxImageSide = 8192;    // pixels per side of a sweep image
inline constexpr int kMaxSweepSpp = 1 << 20;  // keeps counts in uint32 and a pixel's walks < 1 s
inline constexpr int kMaxSweepSpecularSpp = 1 << 16;  // VNDF samples per roughness and pixel
inline constexpr int kMaxSweepBounces = 16;      // rho^17 <= 0.9^17 ~ 0.17 of p_17: nobody asks
inline constexpr int kMaxSweepShards = 1 << 16;  // far more than tiles a useful sweep has per shard
inline constexpr int kMaxSweepViews = 1 << 16;   // images of one sweep
inline constexpr double kMaxRecordedSeconds = 1e9;  // a duration a file records (31 years)
// Any constant a generated header ships (Eq. 10 coefficients, standard errors, closed-form S3
// coefficients): the committed ones are below 100, and this keeps every one a finite float.
inline constexpr double kMaxShippedMagnitude = 1e6;

// The limit's value: its environment variable if set to a positive integer, else the default.
// A value above the limit's ceiling is an error naming the ceiling.
std::uint64_t limitValue(const Limit& limit);

// Throws gtbake::Error "<what>: <value> <unit> exceed the limit of <N> (set ENV to raise it)"
// when value > the limit.
void checkLimit(const Limit& limit, std::uint64_t value, const std::string& what);

// The most memory this process can have and what sets it: the smaller of the address-space and
// data limits (`ulimit -v`, `ulimit -d`), the memory cgroup's limit (v2 memory.max, v1
// memory.limit_in_bytes) and the physical memory. bytes is UINT64_MAX when none is known.
struct MemoryBound {
  std::uint64_t bytes = UINT64_MAX;
  std::string what;  // "the address-space limit (ulimit -v)", ...
};
MemoryBound memoryBound();

// Checks, before any work, the memory a command's options imply: throws gtbake::Error
// "<what>: an estimated 4.8 GB of memory exceed <the bound> of 4.0 GB" when `bytes` exceed
// memoryBound(), and checkLimit(limit, bytes, what) when `limit` is given.
void checkMemoryEstimate(std::uint64_t bytes, const std::string& what,
                         const Limit* limit = nullptr);

// Reads a whole regular file (not a FIFO, device or directory: those are refused without being
// opened for reading, so a FIFO cannot block), at most kMaxInputBytes. Throws gtbake::Error.
std::string readRegularFile(const std::filesystem::path& path);
// The same, refusing before reading anything a file of more than `max_bytes` (the size its
// reader expects at most, e.g. a glTF buffer's byteLength).
std::string readRegularFile(const std::filesystem::path& path, std::uint64_t max_bytes);

// Deepest nesting of arrays and objects in JSON text (strings are skipped); stops counting at
// `stop_at` + 1 so a hostile file costs one linear scan.
int jsonNestingDepth(std::string_view text, int stop_at);

// Reads and parses a JSON file after checking its size and nesting depth (kMaxJsonDepth);
// throws a one-line gtbake::Error naming the file.
nlohmann::json readJsonFile(const std::filesystem::path& path);

// The same for JSON text already read (e.g. verified against an output-set manifest); `where`
// names its file in errors.
nlohmann::json parseJsonText(std::string_view text, const std::string& where);

// An integer member in [lo, hi], without get<int>()'s silent truncation; one-line error
// naming `where` and the key otherwise.
std::int64_t jsonInteger(const nlohmann::json& object, const char* key, std::int64_t lo,
                         std::int64_t hi, const std::string& where);

// `name` as a file directly or below `dir`: refuses absolute names, ".." components (also
// percent-encoded) and empty names, so a `file` entry of sweep.json or gtso.json cannot point
// outside its directory. Returns dir / name.
std::filesystem::path fileInsideDirectory(const std::filesystem::path& dir, const std::string& name,
                                          const std::string& where);

// A finite number member in [lo, hi] (integers accepted); one-line error naming `where` and the
// key otherwise. Readers take every number through it or jsonInteger (docs/limits.md §Values).
double jsonNumber(const nlohmann::json& object, const char* key, double lo, double hi,
                  const std::string& where);

// The member `key` of a JSON object; one-line error "<where>: missing key "KEY"" otherwise.
const nlohmann::json& jsonMember(const nlohmann::json& object, const std::string& key,
                                 const std::string& where);

// A constant the generated code ships, or a standard error of one (non_negative): jsonNumber
// within ±kMaxShippedMagnitude, so it prints as a finite float literal (docs/limits.md §Values).
double shippedNumber(const nlohmann::json& object, const std::string& key, const std::string& where,
                     bool non_negative = false);

// Percent-decodes a URI path ("%2e" -> "."); malformed escapes are kept as written.
std::string percentDecode(const std::string& text);

}  // namespace gtbake
