#include <unistd.h>

#include <cstdlib>
#include <filesystem>

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

}  // namespace gtbake::fuzz
