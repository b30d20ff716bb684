// Single files that are never left half-written (docs/limits.md "Output sets").
//
// A file gtbake writes on its own (a sweep tile, shard.json, a PNG or EXR outside a set) goes first
// to "<name>.gtbake-tmp-<pid>" in the same directory, is written with checked write(2) calls and
// fsync(2), and is renamed over the final name only once complete (rename(2) is atomic within one
// file system). A run that fails leaves any earlier good file where it stood and removes its
// temporary file on the way out (exceptions unwind through AtomicOutput's destructor); SIGINT,
// SIGTERM and SIGHUP remove every temporary file of the process before it dies. A FIFO, socket or
// device node is never replaced. Whole sets of files switch together through OutputSet
// (output_set.h), which stages them in a directory beside the output directory instead.
//
// Test hooks: when the environment variable GTBAKE_TEST_FAIL_WRITE is set, a write whose final
// file name contains its value fails half-way as a full disk would (ENOSPC);
// GTBAKE_TEST_KILL_AT=<point> makes testKillPoint(<point>) kill the process with SIGKILL.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

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
  int slot_ = -1;
  bool committed_ = false;
};

// Writes `bytes` to `path` atomically. Throws gtbake::Error if any write fails (disk full, ...).
void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

// Writes `bytes` to the new file `path` (created or truncated) with checked writes and fsync;
// `name` is the final name reported in errors. Throws gtbake::Error.
void writeBytesChecked(const std::filesystem::path& path, std::string_view bytes,
                       const std::filesystem::path& name);

// Creates `dir` (and parents) or throws gtbake::Error with a one-line reason.
void ensureDirectory(const std::filesystem::path& dir);

// `path` relative to directory `base` (both made absolute first), "." when they are the same.
// Generated files record their inputs this way, so a record does not depend on where the run
// happened (luts/ reproduces from any --out).
std::string relativePath(const std::filesystem::path& path, const std::filesystem::path& base);

// Reads a whole file; throws gtbake::Error naming the file if it is missing or unreadable.
std::string readFile(const std::filesystem::path& path);

// Registers a temporary file or directory the signal handler removes (SIGINT/SIGTERM/SIGHUP);
// returns a slot for unregisterTemporary (-1 if the table is full: the path is then only
// removed by the normal unwinding). Installs the handlers on first use.
int registerTemporary(const std::filesystem::path& path);
void unregisterTemporary(int slot);

// Removes the regular files "*.gtbake-tmp-<pid>" in `dir` left by a gtbake process that no longer
// runs, printing one line per file on stderr; temporaries of a live process are left alone and
// reported, and no other name is touched (a user's "thesis.tmp-4242" stays). Returns the removed
// paths.
std::vector<std::filesystem::path> cleanStaleTemporaries(const std::filesystem::path& dir);
// True when `path` is named as a single-file temporary of a process that no longer runs.
bool isStaleTemporary(const std::filesystem::path& path);

// Throws gtbake::Error "<what> <path> is a FIFO (named pipe), ..." when `path` exists (through
// symlinks) and is a FIFO, socket or device node; anything else passes.
void refuseSpecialFile(const std::filesystem::path& path, const std::string& what);

// fsync(2) of a directory, so the names created in it are durable. Throws gtbake::Error.
void syncDirectory(const std::filesystem::path& dir);

// True when process `pid` exists (also when it belongs to another user).
bool processIsRunning(long pid);

// The GTBAKE_TEST_KILL_AT hook: SIGKILLs the process when the variable equals `point`.
void testKillPoint(const char* point);

}  // namespace gtbake
