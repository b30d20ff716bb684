// Stage directories: where the new content of an output directory is assembled before it
// switches into place with one renameat2(RENAME_EXCHANGE) (docs/limits.md "Output sets").
//
// A stage of directory D is "<parent of D>/.<name of D>.gtbake-stage-<pid>-<n>/", on D's file
// system, holding a marker file (gtbake-stage.json: the tool, pid, process start time and D) and
// tree/, the future D. Only directories named so and marked by a process that no longer runs
// (or empty, from a process that died creating them) are ever removed as stale.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace gtbake {

// True for a name of the form ".<dir>.gtbake-stage-<pid>-<n>".
bool isStageDirectoryName(const std::string& name);

// Throws gtbake::Error, before anything is written, when `real_dir` is a mount point or its file
// system cannot exchange two directories atomically. `shown` names the directory in errors.
void checkSwitchable(const std::filesystem::path& real_dir, const std::filesystem::path& shown);

// Removes the stale stage directories of `real_dir` beside it, one note on stderr each.
void cleanStaleStages(const std::filesystem::path& real_dir);

class StagedDirectory {
 public:
  // Creates the stage of `real_dir` (absolute, symlinks resolved). Throws gtbake::Error.
  explicit StagedDirectory(const std::filesystem::path& real_dir);
  ~StagedDirectory();  // removes the stage and whatever it holds (the new or the old tree)
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  // The future content of the directory.
  const std::filesystem::path& tree() const { return tree_; }

  // Brings into tree(), recursively, every entry of the live directory that tree() does not hold
  // yet and `leave_out(live path, path relative to the directory)` does not exclude: hard links
  // (a copy where linking fails), symlinks as symlinks, directories with their permissions.
  // Stage directories met inside are left out when stale and moved along when this process owns
  // them.
  void replicate(
      const std::function<bool(const std::filesystem::path&, const std::string&)>& leave_out);
  // fsync(2) of every directory of the stage.
  void sync() const;
  // Exchanges tree() with the live directory (a plain rename if the directory has gone), syncs
  // the parent and removes the old tree. Throws gtbake::Error, the live directory untouched, if
  // the exchange fails.
  void switchIn();

 private:
  std::filesystem::path dir_;
  std::filesystem::path container_;
  std::filesystem::path tree_;
  int slot_ = -1;
};

}  // namespace gtbake
