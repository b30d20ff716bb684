// Output sets: the files one command writes, switched into place whole and verified by every
// reader (docs/limits.md "Output sets").
//
// A command stages each output with OutputSet::add (or adopt, for a file it already wrote into
// the directory) into a stage directory beside the output directory (output_stage.h); nothing in
// the output directory changes. commit() then brings every other entry of the directory into the
// stage as hard links (the user's files, other commands' sets, nested directories, recursively),
// leaving out this command's previous set, writes "<command>.manifest.json" (the file names,
// sizes, SHA-256 hashes, the command's settings and the gtbake version), fsyncs, and exchanges the
// stage with the directory in one renameat2(RENAME_EXCHANGE). At every instant the directory holds
// the previous complete set or the new one, each matching its manifest: a run that fails,
// runs out of space or is killed at any step leaves the previous set. The set's directory is
// locked for the set's life (output_lock.h); commands also lock it for their whole run. Readers
// call readOutputSet() and check every file they read with OutputManifest::verify(), which also
// catches a file edited or replaced after the run.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
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
  // readVerified, parsed as JSON; "<dir/name>: not valid JSON (…)" when it does not parse.
  nlohmann::json readVerifiedJson(const std::string& name) const;
};

// The manifest's file name for `command` ("sweep" -> "sweep.manifest.json").
std::string manifestFileName(const std::string& command);

class OutputLock;
class StagedDirectory;

class OutputSet {
 public:
  // Creates `dir` if needed, locks it (OutputLock: a directory another gtbake writes, a FIFO or
  // device, a mount point are refused) and creates the stage. Changes nothing in `dir` until
  // commit(). `command` names the manifest (see manifestFileName).
  OutputSet(std::filesystem::path dir, std::string command);
  ~OutputSet();  // not committed: removes the stage and everything staged
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  const std::filesystem::path& dir() const { return dir_; }

  // Stages `bytes` as dir/name (name relative, no "..", subdirectories allowed and created).
  void add(const std::string& name, std::string_view bytes);
  // Makes dir/name, a regular file already in the directory (a sweep's checkpointed tile), part
  // of the set: commit() links it into the stage and records the bytes linked.
  void adopt(const std::string& name);
  // Records the settings that produced the set (copied into the manifest verbatim).
  void setSettings(nlohmann::ordered_json settings) { settings_ = std::move(settings); }
  // Switches the directory to the new set (see above). Throws gtbake::Error, the previous set in
  // place. Returns the manifest as written.
  OutputManifest commit();

 private:
  struct Staged {
    OutputFile file;
    bool adopted = false;
  };
  // Checks `name` for add/adopt and returns its path in the directory.
  std::filesystem::path checkName(const std::string& name) const;
  std::filesystem::path dir_;
  std::string command_;
  nlohmann::ordered_json settings_ = nlohmann::ordered_json::object();
  std::unique_ptr<OutputLock> lock_;
  std::unique_ptr<StagedDirectory> stage_;
  std::vector<Staged> staged_;
  bool committed_ = false;
};

// Reads and checks dir/<command>.manifest.json (sizes and hashes are checked per file by
// OutputManifest::verify/readVerified). Throws gtbake::Error saying which command to rerun when
// the manifest is missing, malformed, from another command, or lists an unsafe name.
OutputManifest readOutputSet(const std::filesystem::path& dir, const std::string& command);

// Makes the files already in place (`names`, relative to dir) an output set of `command`, switched
// in like any other (adopt), for test fixtures that assemble a set from files they wrote.
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
// is not a directory, a FIFO, socket or device node, and is not one of the command's input files.
void checkOutputFile(const std::filesystem::path& out, const std::string& option,
                     const std::vector<std::filesystem::path>& inputs);

}  // namespace gtbake
