#include "common/output_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <system_error>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_stage.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

constexpr const char* kLockSuffix = ".gtbake-lock";

// The lock files this process holds: path -> descriptor and holders (reentrancy).
struct HeldLock {
  int fd = -1;
  int count = 0;
  int slot = -1;
};
std::map<std::string, HeldLock> g_held;
std::mutex g_held_mutex;

fs::path lockFileOf(const fs::path& real_dir) {
  return real_dir.parent_path() / ("." + real_dir.filename().string() + kLockSuffix);
}

bool isLockFileName(const std::string& name) {
  const std::size_t suffix = std::strlen(kLockSuffix);
  return name.size() > suffix + 1 && name[0] == '.' &&
         name.compare(name.size() - suffix, suffix, kLockSuffix) == 0;
}

bool heldHere(const std::string& lock_file) {
  std::lock_guard<std::mutex> guard(g_held_mutex);
  return g_held.count(lock_file) != 0;
}

// "pid N" from the lock file's text, or "" when it names none.
std::string holderOf(int fd) {
  char text[32] = {};
  const ssize_t n = ::pread(fd, text, sizeof(text) - 1, 0);
  if (n <= 0) return "";
  const long pid = std::strtol(text, nullptr, 10);
  return pid > 0 ? "pid " + std::to_string(pid) : "";
}

std::string busyMessage(const fs::path& dir, const std::string& holder) {
  return dir.string() + " is being written by another gtbake" +
         (holder.empty() ? std::string() : " (" + holder + ")") +
         ": wait for it to finish, or write somewhere else";
}

// True when `fd` is still the file `path` names (a lock file removed by its last holder and
// created again by a newer writer is another file).
bool stillNamed(int fd, const fs::path& path) {
  struct stat by_fd {};
  struct stat by_name {};
  return ::fstat(fd, &by_fd) == 0 && ::lstat(path.c_str(), &by_name) == 0 &&
         by_fd.st_dev == by_name.st_dev && by_fd.st_ino == by_name.st_ino;
}

// Opens and locks `path` exclusively without waiting; throws busyMessage(dir) if it is taken.
int takeLock(const fs::path& path, const fs::path& dir) {
  for (;;) {
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) {
      throw Error("cannot lock " + dir.string() + ": cannot create " + path.string() + ": " +
                  std::strerror(errno) + " (gtbake locks and stages beside the directory)");
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const std::string holder = holderOf(fd);
      ::close(fd);
      throw Error(busyMessage(dir, holder));
    }
    if (stillNamed(fd, path)) {
      // The pid is only for the messages of other writers; the lock is held either way.
      const std::string text = std::to_string(::getpid()) + "\n";
      if (::ftruncate(fd, 0) == 0) (void)!::pwrite(fd, text.data(), text.size(), 0);
      return fd;
    }
    ::close(fd);
  }
}

// Throws when a directory holding `real_dir` is locked by another process.
void refuseLockedAncestors(const fs::path& real_dir, const fs::path& shown) {
  for (fs::path dir = real_dir.parent_path(); dir.has_relative_path(); dir = dir.parent_path()) {
    const fs::path lock_file = lockFileOf(dir);
    if (heldHere(lock_file.string())) continue;
    const int fd = ::open(lock_file.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0) continue;
    const bool busy = ::flock(fd, LOCK_SH | LOCK_NB) != 0;
    const std::string holder = busy ? holderOf(fd) : "";
    ::close(fd);
    if (busy) {
      throw Error(busyMessage(dir, holder) + " (it holds " + shown.string() + ")");
    }
  }
}

void refuseNonDirectory(const fs::path& dir) {
  refuseSpecialFile(dir, "output directory");
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    throw Error("output directory " + dir.string() + " exists and is not a directory");
  }
}

// Releases one hold of `lock_file`; the last one removes the file and unlocks it.
void release(const std::string& lock_file) {
  std::lock_guard<std::mutex> guard(g_held_mutex);
  auto it = g_held.find(lock_file);
  if (it == g_held.end() || --it->second.count > 0) return;
  if (stillNamed(it->second.fd, lock_file)) ::unlink(lock_file.c_str());
  ::close(it->second.fd);
  unregisterTemporary(it->second.slot);
  g_held.erase(it);
}

}  // namespace

fs::path realOutputDirectory(const fs::path& dir) {
  std::error_code ec;
  fs::path real = fs::weakly_canonical(fs::absolute(dir), ec);
  if (ec) throw Error("cannot resolve " + dir.string() + ": " + ec.message());
  if (!real.has_filename() && real.has_relative_path()) real = real.parent_path();
  return real;
}

OutputLock::OutputLock(const fs::path& dir) {
  refuseNonDirectory(dir);
  real_ = realOutputDirectory(dir);
  if (!real_.has_relative_path()) {
    throw Error("cannot write an output set at " + real_.string() + ": name a directory below it");
  }
  refuseNonDirectory(real_);
  refuseLockedAncestors(real_, dir);  // before creating anything; again once locked (the race)
  ensureDirectory(real_.parent_path());
  lock_file_ = lockFileOf(real_).string();
  {
    std::lock_guard<std::mutex> guard(g_held_mutex);
    auto it = g_held.find(lock_file_);
    if (it != g_held.end()) {
      ++it->second.count;
      return;
    }
  }
  checkSwitchable(real_, dir);
  const int fd = takeLock(lock_file_, dir);
  {
    std::lock_guard<std::mutex> guard(g_held_mutex);
    g_held[lock_file_] = {fd, 1, registerTemporary(lock_file_)};
  }
  try {
    refuseLockedAncestors(real_, dir);
    cleanStaleStages(real_);
  } catch (...) {
    release(lock_file_);
    throw;
  }
}

OutputLock::~OutputLock() {
  release(lock_file_);
}

namespace {

// Locks `path` exclusively, waiting (with a note) while another writer holds it; -1 if the file
// is gone (its writer finished and removed it).
int waitForLock(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) return -1;
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const std::string holder = holderOf(fd);
    std::fprintf(stderr, "gtbake: note: waiting for %s, which writes inside %s\n",
                 holder.empty() ? "another gtbake" : holder.c_str(), path.parent_path().c_str());
    while (::flock(fd, LOCK_EX) != 0 && errno == EINTR) {
    }
  }
  return fd;
}

}  // namespace

NestedLocks::NestedLocks(const fs::path& real_dir) {
  // Per directory: first its lock files (so a nested commit finishes before we look inside the
  // directory it switches), then its subdirectories.
  std::vector<fs::path> pending = {real_dir};
  while (!pending.empty()) {
    const fs::path dir = pending.back();
    pending.pop_back();
    std::vector<fs::path> locks, subdirs;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      std::error_code type_error;
      const std::string name = entry.path().filename().string();
      if (entry.is_symlink(type_error)) continue;
      if (entry.is_directory(type_error)) {
        if (!isStageDirectoryName(name)) subdirs.push_back(entry.path());
      } else if (isLockFileName(name) && !heldHere(entry.path().string())) {
        locks.push_back(entry.path());
      }
    }
    for (const fs::path& lock_file : locks) {
      const int fd = waitForLock(lock_file);
      if (fd >= 0) held_.emplace_back(lock_file.string(), fd);
    }
    pending.insert(pending.end(), subdirs.begin(), subdirs.end());
  }
}

NestedLocks::~NestedLocks() {
  for (const auto& [path, fd] : held_) ::close(fd);
}

bool NestedLocks::took(const fs::path& path) const {
  for (const auto& [held, fd] : held_) {
    if (held == path.string()) return true;
  }
  return false;
}

}  // namespace gtbake
