// Test helpers every suite shares: a scratch directory that cleans up after itself, and whole-file
// reads for byte comparisons.
#pragma once

#include <filesystem>
#include <string>

namespace gtbake::test {

// A fresh, empty directory under the system temp dir, named gtbake-<tag>-<pid> (CTest runs
// tests in parallel, one process each) and removed with everything in it by the destructor.
class TempDir {
 public:
  explicit TempDir(const std::string& tag);
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// The file's bytes, or "" if it cannot be read (tests compare bytes; a missing file then fails
// the comparison rather than throwing).
std::string readBytes(const std::filesystem::path& path);

}  // namespace gtbake::test
