// Output sets: the files one command writes, committed together and verified by every reader.
//
// A command stages each output with OutputSet::add (written to "<name>.tmp-<pid>" with checked
// writes; nothing final is touched). commit() then removes the old manifest, renames every staged
// file into place and writes "<dir>/<command>.manifest.json" last: the file names, sizes,
// SHA-256 hashes, the command's settings and the gtbake version. A run that fails or is
// interrupted before commit leaves the previous set intact and valid; one killed inside commit's
// renames (milliseconds) leaves no manifest, so readers refuse the directory instead of mixing
// old and new files. Readers call readOutputSet() and check every file they read with
// OutputManifest::verify(), which also catches a file edited or replaced after the run.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace gtbake {

struct OutputFile {
  std::string name;  // relative to the set's directory ("sweep.json", "cavity.exr")
  std::uint64_t size = 0;
  std::string sha256;  // 64 lower-case hex digits
};

struct OutputManifest {
  std::filesystem::path dir;
  std::string command;  // "sweep", "fit", "gtso", "export", ...
  std::string gtbake_version;
  nlohmann::ordered_json settings;
  std::vector<OutputFile> files;

  // The entry for `name`, or nullptr.
  const OutputFile* find(const std::string& name) const;
  // Throws gtbake::Error unless `bytes` are exactly the bytes the set recorded for `name`.
  void verify(const std::string& name, std::string_view bytes) const;
  // Reads dir/name (a regular file inside dir), verifies it and returns its bytes.
  std::string readVerified(const std::string& name) const;
};

// The manifest's file name for `command` ("sweep" -> "sweep.manifest.json").
std::string manifestFileName(const std::string& command);

class OutputSet {
 public:
  // Creates `dir` if needed and removes stale temporaries of killed runs in it. Writes nothing
  // else until commit(). `command` names the manifest (see manifestFileName).
  OutputSet(std::filesystem::path dir, std::string command);
  ~OutputSet();  // not committed: removes every staged temporary file
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  const std::filesystem::path& dir() const { return dir_; }

  // Stages `bytes` as dir/name (name relative, no "..", subdirectories allowed and created).
  void add(const std::string& name, std::string_view bytes);
  // Records the settings that produced the set (copied into the manifest verbatim).
  void setSettings(nlohmann::ordered_json settings) { settings_ = std::move(settings); }
  // Renames every staged file into place, then writes the manifest. Throws gtbake::Error.
  // Returns the manifest as written.
  OutputManifest commit();

 private:
  struct Staged {
    OutputFile file;
    std::filesystem::path temp;
    int slot = -1;
  };
  std::filesystem::path dir_;
  std::string command_;
  nlohmann::ordered_json settings_ = nlohmann::ordered_json::object();
  std::vector<Staged> staged_;
  bool committed_ = false;
};

// Reads and checks dir/<command>.manifest.json (sizes and hashes are checked per file by
// OutputManifest::verify/readVerified). Throws gtbake::Error saying which command to rerun when
// the manifest is missing, malformed, from another command, or lists an unsafe name.
OutputManifest readOutputSet(const std::filesystem::path& dir, const std::string& command);

// Writes dir/<command>.manifest.json for files already in place (`names`, relative to dir), for
// tools that assemble a set from files they have just written (shard merges, test fixtures).
OutputManifest sealOutputSet(const std::filesystem::path& dir, const std::string& command,
                             const std::vector<std::string>& names,
                             nlohmann::ordered_json settings = nlohmann::ordered_json::object());
// Re-hashes the files an existing manifest lists and rewrites it (tests that edit a set on
// purpose to exercise a reader's own checks).
OutputManifest resealOutputSet(const std::filesystem::path& dir, const std::string& command);

// The paths of a set's files and of its manifest, if dir holds a manifest for `command` (else
// an empty list): the inputs an output must never replace.
std::vector<std::filesystem::path> outputSetPaths(const std::filesystem::path& dir,
                                                  const std::string& command);

// Every file of the set, read and verified; throws on the first mismatch.
void verifyOutputSet(const OutputManifest& manifest);

// True when `candidate` and `input` name the same file or `candidate` is a directory that holds
// it (both resolved through symlinks where they exist): an output may never replace an input.
bool sameOrInside(const std::filesystem::path& candidate, const std::filesystem::path& input);

// Checks, before anything is written, that the output file `out` (named by `option` in errors)
// is not a directory and is not one of the command's input files.
void checkOutputFile(const std::filesystem::path& out, const std::string& option,
                     const std::vector<std::filesystem::path>& inputs);

}  // namespace gtbake
