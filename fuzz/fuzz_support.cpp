#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/sha256.h"
#include "fuzz_target.h"

namespace gtbake::fuzz {

namespace {
std::string g_dir;
void removeScratch() {
  std::error_code ignored;
  std::filesystem::remove_all(g_dir, ignored);
}
}  // namespace

const std::string& scratchDir() {
  if (g_dir.empty()) {
    g_dir = (std::filesystem::temp_directory_path() / ("gtbake-fuzz-" + std::to_string(::getpid())))
                .string();
    std::filesystem::create_directories(g_dir);
    std::atexit(removeScratch);
  }
  return g_dir;
}

void requireOneLine(const std::exception& e) {
  if (std::strchr(e.what(), '\n') != nullptr) {
    std::fprintf(stderr, "multi-line error: %s\n", e.what());
    std::abort();
  }
}

void writeSet(const std::string& dir, const std::string& command,
              const std::vector<std::pair<std::string, std::string>>& files) {
  std::filesystem::create_directories(dir);
  nlohmann::json listed = nlohmann::json::array();
  for (const auto& [name, bytes] : files) {
    std::ofstream(dir + "/" + name, std::ios::binary | std::ios::trunc) << bytes;
    listed.push_back({{"name", name}, {"size", bytes.size()}, {"sha256", sha256Hex(bytes)}});
  }
  const nlohmann::json manifest = {{"command", command},
                                   {"gtbake_version", "fuzz"},
                                   {"settings", nlohmann::json::object()},
                                   {"files", listed}};
  std::ofstream(dir + "/" + command + ".manifest.json", std::ios::trunc) << manifest.dump();
}

}  // namespace gtbake::fuzz
