// Exclusive locks on output directories (docs/limits.md "Output sets", "The lock").
//
// A command that writes into directory D holds an flock(2) on "<parent of D>/.<name of
// D>.gtbake-lock" for its whole run: the lock file lies outside D, so it survives D being exchanged
// with a staged copy. A second writer of D, or of a directory inside D, or of a directory that
// holds D, fails at once with one line naming the directory and the pid that holds it. Locks are
// reentrant within a process (`gtbake all` locks luts/ and each stage locks it again) and the lock
// file is removed when its last holder in the process lets go.
//
// Nesting: a writer of D checks, right after taking its own lock, that no directory holding D is
// locked by another process. A commit of D waits (with a note on stderr) for the writers of
// directories inside D that started before it, by locking every lock file found inside D; its new
// tree leaves those lock files out.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace gtbake {

// `dir` made absolute with its symlinks resolved (a missing tail is appended to its nearest
// existing ancestor, resolved).
std::filesystem::path realOutputDirectory(const std::filesystem::path& dir);

class OutputLock {
 public:
  // Locks `dir` (creating its parent if needed, not `dir` itself); refuses a FIFO, socket, device
  // or other non-directory, a mount point, a file system that cannot exchange directories, and a
  // directory another process writes. Removes the stale stage directories of killed runs beside it.
  explicit OutputLock(const std::filesystem::path& dir);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  // The directory as locked: absolute, symlinks resolved.
  const std::filesystem::path& realDir() const { return real_; }

 private:
  std::filesystem::path real_;
  std::string lock_file_;
};

// The lock files found inside a directory (recursively), locked for the length of one commit.
class NestedLocks {
 public:
  explicit NestedLocks(const std::filesystem::path& real_dir);
  ~NestedLocks();
  NestedLocks(const NestedLocks&) = delete;
  NestedLocks& operator=(const NestedLocks&) = delete;

  // True when `path` is a lock file this commit took (finished or stale: left out of the tree).
  bool took(const std::filesystem::path& path) const;

 private:
  std::vector<std::pair<std::string, int>> held_;  // lock file, descriptor
};

}  // namespace gtbake
