// Runs the built gtbake binary as a user would and captures what it prints.
#pragma once

#include <filesystem>
#include <string>

namespace gtbake::test {

struct RunResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// Runs `gtbake <arguments>` through /bin/sh (arguments are passed as written) with no stdin.
RunResult runGtbake(const std::string& arguments);

// A fresh, empty directory under the system temp dir, removed by the destructor.
class TempDir {
 public:
  explicit TempDir(const std::string& tag);
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

std::string readBytes(const std::filesystem::path& path);

}  // namespace gtbake::test
