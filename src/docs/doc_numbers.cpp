#include "docs/doc_numbers.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"

namespace gtbake::docs {
namespace {

constexpr const char* kOpen = "<!--@";
constexpr const char* kClose = "-->";
constexpr const char* kUnicodeMinus = "\xE2\x88\x92";  // U+2212, as docs write negative numbers
// A quoted number never needs more bytes than this (sign, digits, point, exponent).
constexpr std::size_t kMaxNumberBytes = 48;

int lineAt(const std::string& text, std::size_t pos) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + pos, '\n'));
}

bool startsWith(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

// Where the number that ends at `end` begins, or npos if none ends there. The number is the
// longest suffix of text[..end) of the form [sign] digits [. digits] [e [sign] digits].
// A word quoted by a "%s" marker (a status a JSON string or boolean holds, e.g. upper_bound):
// letters, digits and '_' immediately before the marker.
std::size_t wordBegin(const std::string& text, std::size_t end) {
  std::size_t begin = end;
  while (begin > 0 && begin + kMaxNumberBytes > end &&
         (std::isalnum(static_cast<unsigned char>(text[begin - 1])) || text[begin - 1] == '_'))
    --begin;
  return begin == end ? std::string::npos : begin;
}

std::size_t numberBegin(const std::string& text, std::size_t end) {
  static const std::regex kNumber(
      "(?:[+-]|\xE2\x88\x92)?(?:[0-9]+(?:\\.[0-9]*)?|\\.[0-9]+)(?:[eE][+-]?[0-9]+)?$");
  const std::size_t from = end > kMaxNumberBytes ? end - kMaxNumberBytes : 0;
  std::smatch match;
  const std::string window = text.substr(from, end - from);
  if (!std::regex_search(window, match, kNumber)) return std::string::npos;
  return from + static_cast<std::size_t>(match.position(0));
}

std::vector<std::string> splitFields(const std::string& body) {
  std::istringstream in(body);
  std::vector<std::string> fields;
  for (std::string field; in >> field;) fields.push_back(field);
  return fields;
}

// Checks that `format` is exactly one conversion of a double: %[flags][width][.precision]conv,
// or "%s" for a JSON string quoted as a word.
std::string formatProblem(const std::string& format) {
  if (format == kWordFormat) return {};
  std::size_t i = 0;
  if (format.empty() || format[i++] != '%') return "must start with %";
  while (i < format.size() && std::string("-+ #0").find(format[i]) != std::string::npos) ++i;
  while (i < format.size() && std::isdigit(static_cast<unsigned char>(format[i]))) ++i;
  if (i < format.size() && format[i] == '.') {
    ++i;
    while (i < format.size() && std::isdigit(static_cast<unsigned char>(format[i]))) ++i;
  }
  if (i >= format.size() || std::string("fFeEgG").find(format[i]) == std::string::npos) {
    return "needs one conversion f, F, e, E, g or G";
  }
  if (i + 1 != format.size()) return "has text after the conversion";
  return {};
}

std::optional<double> parseScale(const std::string& field) {
  if (field.size() < 2 || field[0] != 'x') return std::nullopt;
  std::size_t used = 0;
  try {
    const double scale = std::stod(field.substr(1), &used);
    if (used + 1 != field.size() || !std::isfinite(scale)) return std::nullopt;
    return scale;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// Parses the comment body "FILE POINTER FORMAT [xSCALE]" into `marker`, or says what is wrong.
std::string parseBody(const std::string& body, NumberMarker& marker) {
  const std::vector<std::string> fields = splitFields(body);
  if (fields.size() != 3 && fields.size() != 4) {
    return "expected FILE POINTER FORMAT [xSCALE], got " + std::to_string(fields.size()) +
           " fields";
  }
  marker.file = fields[0];
  marker.pointer = fields[1];
  marker.format = fields[2];
  if (marker.file.empty() || marker.file[0] == '/' || marker.file.find("..") != std::string::npos) {
    return "FILE '" + marker.file + "' must be relative to the artifact directory";
  }
  try {
    (void)nlohmann::json::json_pointer(marker.pointer);
  } catch (const nlohmann::json::exception&) {
    return "POINTER '" + marker.pointer + "' is not an RFC 6901 JSON pointer";
  }
  if (const std::string problem = formatProblem(marker.format); !problem.empty()) {
    return "FORMAT '" + marker.format + "' " + problem;
  }
  if (fields.size() == 4) {
    const std::optional<double> scale = parseScale(fields[3]);
    if (!scale) return "SCALE '" + fields[3] + "' must be x<number>, e.g. x100";
    marker.scale = *scale;
  }
  return {};
}

// True if `pos` lies in Markdown code: a fenced block (``` lines) or an inline `code span`.
// Docs show the marker syntax itself there, so those comments are examples, not markers.
bool inCode(const std::string& text, std::size_t pos) {
  const std::size_t newline = text.rfind('\n', pos);
  const std::size_t line_begin = newline == std::string::npos ? 0 : newline + 1;
  if (std::count(text.begin() + line_begin, text.begin() + pos, '`') % 2 == 1) return true;
  bool fenced = false;
  for (std::size_t line = 0; line < line_begin; line = text.find('\n', line) + 1) {
    const std::size_t first = text.find_first_not_of(' ', line);
    if (text.compare(first, 3, "```") == 0) fenced = !fenced;
  }
  return fenced;
}

}  // namespace

ParsedDoc parseMarkers(const std::string& text) {
  ParsedDoc doc;
  for (std::size_t open = text.find(kOpen); open != std::string::npos;
       open = text.find(kOpen, open + 1)) {
    if (inCode(text, open)) continue;
    NumberMarker marker;
    marker.line = lineAt(text, open);
    const std::size_t close = text.find(kClose, open);
    const std::size_t newline = text.find('\n', open);
    if (close == std::string::npos || close > newline) {
      doc.malformed.push_back(
          {DocIssue::Kind::kMalformed, marker.line, "marker not closed by --> on the same line"});
      continue;
    }
    const std::size_t body_begin = open + std::char_traits<char>::length(kOpen);
    if (std::string problem = parseBody(text.substr(body_begin, close - body_begin), marker);
        !problem.empty()) {
      doc.malformed.push_back({DocIssue::Kind::kMalformed, marker.line, problem});
      continue;
    }
    const std::size_t begin =
        marker.format == kWordFormat ? wordBegin(text, open) : numberBegin(text, open);
    if (begin == std::string::npos) {
      doc.malformed.push_back(
          {DocIssue::Kind::kMalformed, marker.line, "no number immediately before the marker"});
      continue;
    }
    const unsigned char before = begin > 0 ? static_cast<unsigned char>(text[begin - 1]) : ' ';
    if ((marker.format != kWordFormat && std::isalnum(before)) || before == '.' || before == ',' ||
        before == '_') {
      doc.malformed.push_back({DocIssue::Kind::kMalformed, marker.line,
                               "the number before the marker is glued to '" +
                                   std::string(1, static_cast<char>(before)) +
                                   "' (write it whole)"});
      continue;
    }
    marker.number_begin = begin;
    marker.number_end = open;
    marker.quoted = text.substr(begin, open - begin);
    doc.markers.push_back(std::move(marker));
  }
  return doc;
}

std::string formatNumber(const std::string& format, double value) {
  if (format == kWordFormat) throw Error("format %s quotes a string, not a number");
  if (const std::string problem = formatProblem(format); !problem.empty()) {
    throw Error("format '" + format + "' " + problem);
  }
  char buffer[128];
  const int n = std::snprintf(buffer, sizeof buffer, format.c_str(), value);
  if (n < 0 || static_cast<std::size_t>(n) >= sizeof buffer) {
    throw Error("format '" + format + "' gives more than 127 characters");
  }
  return buffer;
}

ValueLookup jsonLookup(const std::filesystem::path& artifact_dir,
                       const std::filesystem::path& data_dir) {
  // Each file is read and parsed once; a file that fails to parse keeps its error.
  struct Parsed {
    nlohmann::json json;
    std::string error;
  };
  auto cache = std::make_shared<std::map<std::string, Parsed>>();
  return [artifact_dir, data_dir, cache](const std::string& file, const std::string& pointer) {
    auto it = cache->find(file);
    if (it == cache->end()) {
      Parsed parsed;
      static const std::string kData = "data/";
      const std::filesystem::path path = !data_dir.empty() && file.rfind(kData, 0) == 0
                                             ? data_dir / file.substr(kData.size())
                                             : artifact_dir / file;
      try {
        parsed.json = nlohmann::json::parse(readFile(path));
      } catch (const Error& e) {
        parsed.error = e.what();
      } catch (const nlohmann::json::exception& e) {
        parsed.error = path.string() + " is not valid JSON (" + e.what() + ")";
      }
      it = cache->emplace(file, std::move(parsed)).first;
    }
    LookupResult result;
    if (!it->second.error.empty()) {
      result.error = it->second.error;
      return result;
    }
    const nlohmann::json::json_pointer ptr(pointer);
    if (!it->second.json.contains(ptr)) {
      result.error = file + " has no " + pointer;
      return result;
    }
    const nlohmann::json& value = it->second.json.at(ptr);
    if (value.is_string() || value.is_boolean()) {  // for a "%s" marker (true, false too)
      result.text = value.is_string() ? value.get<std::string>() : value.dump();
      result.error = file + " " + pointer + " is string, not a number";
      return result;
    }
    if (!value.is_number()) {
      result.error = file + " " + pointer + " is " + value.type_name() + ", not a number";
      return result;
    }
    result.value = value.get<double>();
    return result;
  };
}

std::optional<std::string> expectedNumber(const NumberMarker& marker, const ValueLookup& lookup,
                                          std::string& error) {
  const LookupResult found = lookup(marker.file, marker.pointer);
  if (marker.format == kWordFormat) {
    if (!found.text)
      error = found.error.empty() ? marker.file + " " + marker.pointer + " is not a string"
                                  : found.error;
    return found.text;
  }
  if (!found.value) {
    error = found.error;
    return std::nullopt;
  }
  std::string text = formatNumber(marker.format, *found.value * marker.scale);
  if (startsWith(marker.quoted, kUnicodeMinus) && startsWith(text, "-")) {
    text.replace(0, 1, kUnicodeMinus);
  }
  return text;
}

CheckResult checkDocument(const std::string& text, const ValueLookup& lookup) {
  const ParsedDoc doc = parseMarkers(text);
  CheckResult result;
  result.issues = doc.malformed;
  result.markers = static_cast<int>(doc.markers.size());
  result.updated_text = text;
  // Back to front, so earlier byte offsets stay valid while the text is edited.
  for (auto it = doc.markers.rbegin(); it != doc.markers.rend(); ++it) {
    std::string error;
    const std::optional<std::string> expected = expectedNumber(*it, lookup, error);
    if (!expected) {
      result.issues.push_back({DocIssue::Kind::kLookup, it->line, error});
      continue;
    }
    if (*expected == it->quoted) continue;
    ++result.mismatches;
    result.issues.push_back({DocIssue::Kind::kMismatch, it->line,
                             "reads " + it->quoted + " but " + it->file + " " + it->pointer + " " +
                                 it->format + " gives " + *expected});
    result.updated_text.replace(it->number_begin, it->number_end - it->number_begin, *expected);
  }
  std::stable_sort(result.issues.begin(), result.issues.end(),
                   [](const DocIssue& a, const DocIssue& b) { return a.line < b.line; });
  return result;
}

}  // namespace gtbake::docs
