// Numbers in docs that come from artifacts: parse, check and update `NUMBER<!--@ ...-->` markers.
//
// Marker syntax (docs/index.md, "Numbers in docs"): a number immediately followed by
//
//   <!--@ FILE POINTER FORMAT [xSCALE]-->
//
// FILE is a JSON file relative to the artifact directory (luts/), or `data/...`, read from the
// data directory (the committed studies outside luts/, jsonLookup), POINTER an RFC 6901 JSON
// pointer into it, FORMAT one printf conversion of a double and nothing else (`%.4f`, `%+.3g`,
// `%.1e`, `%.0f`: flags, width, precision, then f, F, e, E, g or G), and xSCALE an optional factor
// applied first (`x100` for percentages). The number before the
// comment must read exactly as printf(FORMAT, value * SCALE) prints it, except that a leading
// U+2212 minus sign in the doc stands for printf's '-'. Comments inside Markdown code (fenced
// blocks and inline `code spans`) are examples of the syntax and are skipped.
//
// The library is pure text in, text out; apps/gtbake-docs does the file handling.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gtbake::docs {

// The FORMAT of a marker that quotes a JSON string as one word (e.g. a status: upper_bound).
inline constexpr std::string_view kWordFormat = "%s";

// One marker as written in a document.
struct NumberMarker {
  int line = 0;                  // 1-based line of the comment's "<!--@"
  std::size_t number_begin = 0;  // byte range of the quoted number in the text
  std::size_t number_end = 0;
  std::string quoted;   // the number as written (may start with U+2212)
  std::string file;     // relative to the artifact directory
  std::string pointer;  // RFC 6901
  std::string format;   // printf format for one double
  double scale = 1.0;
};

// A problem found in a document, located by line.
struct DocIssue {
  enum class Kind {
    kMalformed,  // the marker does not parse or follows no number
    kLookup,     // the file, the pointer or a number at the pointer is missing
    kMismatch,   // the quoted number differs from the artifact's (fixed by an update)
  };
  Kind kind = Kind::kMalformed;
  int line = 0;
  std::string message;
};

struct ParsedDoc {
  std::vector<NumberMarker> markers;
  std::vector<DocIssue> malformed;  // markers that could not be parsed
};

// Finds every marker in `text`. A comment starting "<!--@" that is not a well-formed marker, or
// that does not follow a number, is reported in `malformed` and skipped.
ParsedDoc parseMarkers(const std::string& text);

// printf(format, value) after checking that `format` converts exactly one double; throws
// gtbake::Error naming the problem otherwise.
std::string formatNumber(const std::string& format, double value);

// Looks a marker's value up: (file, pointer) -> number, or an error message.
struct LookupResult {
  std::optional<double> value;
  std::optional<std::string> text;  // a JSON string (quoted by a "%s" marker)
  std::string error;
};
using ValueLookup =
    std::function<LookupResult(const std::string& file, const std::string& pointer)>;

// Reads FILE under `artifact_dir` (each file parsed once per lookup object) and resolves POINTER.
// A FILE starting with "data/" names a committed study outside luts/ (docs/index.md) and is read
// from `data_dir` instead; with an empty `data_dir` such a FILE is looked up like any other.
ValueLookup jsonLookup(const std::filesystem::path& artifact_dir,
                       const std::filesystem::path& data_dir = {});

// The number a marker should show: its formatted value, in the doc's minus-sign style.
// Returns nullopt and sets `error` when the lookup or the format fails.
std::optional<std::string> expectedNumber(const NumberMarker& marker, const ValueLookup& lookup,
                                          std::string& error);

struct CheckResult {
  std::vector<DocIssue> issues;  // malformed markers, lookup failures and mismatches, by line
  std::string updated_text;      // `text` with every resolvable number set to its expected value
  int markers = 0;
  int mismatches = 0;
};

// Checks every marker of `text` and computes the updated text in one pass.
CheckResult checkDocument(const std::string& text, const ValueLookup& lookup);

}  // namespace gtbake::docs
