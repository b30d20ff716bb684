#include "common/input_limits.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <set>
#include <string>

#include "common/error.h"

namespace gtbake {

namespace fs = std::filesystem;

std::uint64_t limitValue(const Limit& limit) {
  const char* text = std::getenv(limit.env);
  if (text == nullptr || *text == '\0') return limit.fallback;
  char* end = nullptr;
  errno = 0;
  const unsigned long long value = std::strtoull(text, &end, 10);
  if (errno != 0 || *end != '\0' || value == 0 || text[0] == '-') {
    throw Error(std::string(limit.env) + " must be a positive integer, got '" + text + "'");
  }
  if (value > limit.ceiling) {
    throw Error(std::string(limit.env) + " must be at most " + std::to_string(limit.ceiling) +
                " (what the readers survive, docs/limits.md), got " + text);
  }
  return value;
}

void checkLimit(const Limit& limit, std::uint64_t value, const std::string& what) {
  const std::uint64_t max = limitValue(limit);
  if (value <= max) return;
  throw Error(what + ": " + std::to_string(value) + " " + limit.unit + " exceed the limit of " +
              std::to_string(max) + " (set " + limit.env + " to raise it)");
}

namespace {

// The limit in bytes a memory cgroup file states ("max" or unreadable: none).
std::uint64_t cgroupLimit(const fs::path& file) {
  std::FILE* in = std::fopen(file.c_str(), "r");
  if (in == nullptr) return UINT64_MAX;
  unsigned long long value = UINT64_MAX;
  if (std::fscanf(in, "%llu", &value) != 1) value = UINT64_MAX;
  std::fclose(in);
  return value;
}

// This process's memory cgroup limit, from /proc/self/cgroup (v2 "0::PATH", v1 "N:memory:PATH").
std::uint64_t cgroupMemoryLimit() {
  std::FILE* in = std::fopen("/proc/self/cgroup", "r");
  if (in == nullptr) return UINT64_MAX;
  std::uint64_t limit = UINT64_MAX;
  char line[4096];
  while (std::fgets(line, sizeof(line), in) != nullptr) {
    std::string text(line);
    if (!text.empty() && text.back() == '\n') text.pop_back();
    if (text.rfind("0::", 0) == 0) {
      limit = std::min(limit, cgroupLimit("/sys/fs/cgroup" + text.substr(3) + "/memory.max"));
    } else if (const std::size_t at = text.find(":memory:"); at != std::string::npos) {
      limit = std::min(limit, cgroupLimit("/sys/fs/cgroup/memory" + text.substr(at + 8) +
                                          "/memory.limit_in_bytes"));
    }
  }
  std::fclose(in);
  return limit;
}

std::string gigabytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f GB", static_cast<double>(bytes) / 1e9);
  return text;
}

}  // namespace

MemoryBound memoryBound() {
  MemoryBound bound;
  auto consider = [&](std::uint64_t bytes, const char* what) {
    if (bytes < bound.bytes) bound = {bytes, what};
  };
  for (const auto& [resource, what] :
       {std::pair{RLIMIT_AS, "the address-space limit (ulimit -v)"},
        std::pair{RLIMIT_DATA, "the data-segment limit (ulimit -d)"}}) {
    struct rlimit limit {};
    if (::getrlimit(resource, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
      consider(limit.rlim_cur, what);
    }
  }
  consider(cgroupMemoryLimit(), "the memory cgroup's limit");
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages > 0 && page > 0) {
    consider(static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page),
             "the physical memory");
  }
  return bound;
}

void checkMemoryEstimate(std::uint64_t bytes, const std::string& what, const Limit* limit) {
  const MemoryBound bound = memoryBound();
  if (bytes > bound.bytes) {
    throw Error(what + ": an estimated " + gigabytes(bytes) + " of memory exceed " + bound.what +
                " of " + gigabytes(bound.bytes));
  }
  if (limit != nullptr) checkLimit(*limit, bytes, what);
}

std::string readRegularFile(const fs::path& path) {
  return readRegularFile(path, UINT64_MAX);
}

std::string readRegularFile(const fs::path& path, std::uint64_t max_bytes) {
  // O_NONBLOCK: opening a FIFO with no writer must not block; fstat then refuses it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) throw Error("no such file: " + path.string());
    throw Error("cannot read " + path.string() + ": " + std::strerror(errno));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw Error(path.string() + " is not a regular file");
  }
  const auto size = static_cast<std::uint64_t>(st.st_size);
  try {
    checkLimit(kMaxInputBytes, size, path.string());
    if (size > max_bytes) {
      throw Error(path.string() + ": " + std::to_string(size) + " bytes, more than the " +
                  std::to_string(max_bytes) + " expected");
    }
  } catch (...) {
    ::close(fd);
    throw;
  }
  std::string bytes(static_cast<std::size_t>(size), '\0');
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int saved = errno;
      ::close(fd);
      throw Error("cannot read " + path.string() + ": " +
                  (n == 0 ? "the file shrank while being read" : std::strerror(saved)));
    }
    done += static_cast<std::size_t>(n);
  }
  ::close(fd);
  return bytes;
}

int jsonNestingDepth(std::string_view text, int stop_at) {
  int depth = 0, deepest = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
      if (deepest > stop_at) return deepest;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

nlohmann::json parseJsonText(std::string_view text, const std::string& where) {
  const auto max_depth = static_cast<int>(limitValue(kMaxJsonDepth));
  if (jsonNestingDepth(text, max_depth) > max_depth) {
    throw Error(where + ": JSON nested deeper than " + std::to_string(max_depth) + " levels (set " +
                kMaxJsonDepth.env + " to raise the limit)");
  }
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    std::string what = e.what();
    what = what.substr(0, what.find('\n'));
    throw Error(where + ": malformed JSON (" + what + ")");
  }
}

nlohmann::json readJsonFile(const fs::path& path) {
  return parseJsonText(readRegularFile(path), path.string());
}

std::int64_t jsonInteger(const nlohmann::json& object, const char* key, std::int64_t lo,
                         std::int64_t hi, const std::string& where) {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (!object.is_object() || !object.contains(key)) {
    throw Error(where + ": missing integer '" + key + "' (expected in " + range + ")");
  }
  const nlohmann::json& v = object.at(key);
  bool ok = false;
  std::int64_t value = 0;
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    ok = u <= static_cast<std::uint64_t>(hi) && static_cast<std::int64_t>(u) >= lo;
    value = ok ? static_cast<std::int64_t>(u) : 0;
  } else if (v.is_number_integer()) {
    value = v.get<std::int64_t>();
    ok = value >= lo && value <= hi;
  }
  if (!ok)
    throw Error(where + ": '" + key + "' must be an integer in " + range + ", got " + v.dump());
  return value;
}

double jsonNumber(const nlohmann::json& object, const char* key, double lo, double hi,
                  const std::string& where) {
  char range[80];
  std::snprintf(range, sizeof(range), "[%.9g, %.9g]", lo, hi);
  if (!object.is_object() || !object.contains(key)) {
    throw Error(where + ": missing number '" + key + "' (expected in " + range + ")");
  }
  const nlohmann::json& v = object.at(key);
  const double value = v.is_number() ? v.get<double>() : NAN;
  if (!(std::isfinite(value) && value >= lo && value <= hi)) {
    throw Error(where + ": '" + key + "' must be a finite number in " + range + ", got " +
                v.dump());
  }
  return value;
}

std::string percentDecode(const std::string& text) {
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size() && hex(text[i + 1]) >= 0 && hex(text[i + 2]) >= 0) {
      out.push_back(static_cast<char>(16 * hex(text[i + 1]) + hex(text[i + 2])));
      i += 2;
    } else {
      out.push_back(text[i]);
    }
  }
  return out;
}

fs::path fileInsideDirectory(const fs::path& dir, const std::string& name,
                             const std::string& where) {
  const fs::path decoded(percentDecode(name));
  if (name.empty() || decoded.is_absolute() || fs::path(name).is_absolute()) {
    throw Error(where + ": file '" + name + "' must be a relative path inside " + dir.string());
  }
  for (const fs::path& part : {fs::path(name), decoded}) {
    for (const fs::path& component : part) {
      if (component == "..") {
        throw Error(where + ": file '" + name + "' points outside " + dir.string() +
                    " ('..' is not allowed)");
      }
    }
  }
  if (name.find('\0') != std::string::npos) throw Error(where + ": file name contains NUL");
  return dir / name;
}

const nlohmann::json& jsonMember(const nlohmann::json& object, const std::string& key,
                                 const std::string& where) {
  if (!object.is_object() || !object.contains(key)) {
    throw Error(where + ": missing key \"" + key + "\"");
  }
  return object.at(key);
}

double shippedNumber(const nlohmann::json& object, const std::string& key, const std::string& where,
                     bool non_negative) {
  return jsonNumber(object, key.c_str(), non_negative ? 0.0 : -kMaxShippedMagnitude,
                    kMaxShippedMagnitude, where);
}

}  // namespace gtbake
