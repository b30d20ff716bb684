// Small helpers shared by the reliability tests beside tests/support (TempDir, readBytes): writing
// bytes and scoped environment variables.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "support/temp_dir.h"

namespace gtbake::test {

inline void spit(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// What gtbake's writers of `dir` leave beside and inside it while they run: its stage directories
// and lock file (".<dir>.gtbake-*" in the parent) and single-file temporaries ("*.gtbake-tmp-*").
// Empty once every writer has finished or been cleaned up after.
inline std::vector<std::string> gtbakeLeftovers(const std::filesystem::path& dir) {
  std::vector<std::string> found;
  const std::string beside = "." + dir.filename().string() + ".gtbake-";
  for (const auto& e : std::filesystem::directory_iterator(dir.parent_path())) {
    if (e.path().filename().string().rfind(beside, 0) == 0) found.push_back(e.path().string());
  }
  std::error_code ec;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir, ec)) {
    if (e.path().filename().string().find(".gtbake-") != std::string::npos) {
      found.push_back(e.path().string());
    }
  }
  return found;
}

class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_) {
      ::setenv(name_, old_->c_str(), 1);
    } else {
      ::unsetenv(name_);
    }
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

}  // namespace gtbake::test
