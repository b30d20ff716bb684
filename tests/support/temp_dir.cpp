#include "temp_dir.h"

#include <unistd.h>

#include <fstream>
#include <sstream>

namespace gtbake::test {

namespace fs = std::filesystem;

TempDir::TempDir(const std::string& tag) {
  path_ = fs::temp_directory_path() / ("gtbake-" + tag + "-" + std::to_string(::getpid()));
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
}

std::string readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace gtbake::test
