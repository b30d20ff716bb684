// Outputs that are never left half-written.
//
// Every file gtbake writes goes first to "<name>.tmp-<pid>" in the same directory and is renamed
// over the final name only once it is complete (rename(2) is atomic within one file system). A run
// that fails or is interrupted leaves any earlier good file where it stood, and removes its own
// temporary file on the way out (exceptions unwind through AtomicOutput's destructor).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace gtbake {

class AtomicOutput {
 public:
  explicit AtomicOutput(std::filesystem::path final_path);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  // Where the writer should put the bytes (a sibling of the final path).
  const std::filesystem::path& tempPath() const { return temp_; }
  // Renames the temporary file over the final path. Throws gtbake::Error on failure.
  void commit();

 private:
  std::filesystem::path final_;
  std::filesystem::path temp_;
  bool committed_ = false;
};

// Writes `bytes` to `path` atomically. Throws gtbake::Error if the directory is not writable.
void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

// Calls `writer(tempPath)` and commits on success; for libraries that write by file name.
void writeAtomically(const std::filesystem::path& path,
                     const std::function<void(const std::filesystem::path&)>& writer);

// Creates `dir` (and parents) or throws gtbake::Error with a one-line reason.
void ensureDirectory(const std::filesystem::path& dir);

// `path` relative to directory `base` (both made absolute first), "." when they are the same.
// Generated files record their inputs this way, so a record does not depend on where the run
// happened (luts/ reproduces from any --out).
std::string relativePath(const std::filesystem::path& path, const std::filesystem::path& base);

// Reads a whole file; throws gtbake::Error naming the file if it is missing or unreadable.
std::string readFile(const std::filesystem::path& path);

}  // namespace gtbake
