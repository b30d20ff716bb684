#include "common/atomic_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <system_error>

#include "common/error.h"
#include "common/input_limits.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

constexpr const char* kTemporaryInfix = ".gtbake-tmp-";

// Temporary paths of this process for the signal handler: fixed slots, so the handler neither
// allocates nor locks (unlink and rmdir are async-signal-safe).
constexpr int kTemporarySlots = 512;
constexpr std::size_t kSlotPathBytes = 4096;
struct TemporarySlot {
  std::atomic<bool> used{false};
  char path[kSlotPathBytes];
};
std::array<TemporarySlot, kTemporarySlots> g_temporaries;
std::mutex g_temporaries_mutex;
std::once_flag g_handlers_installed;

// Removes the file or directory tree `name` (relative to `parent_fd`) with async-signal-safe
// calls only (unlinkat, openat, getdents64), at most kMaxDepth directories deep.
constexpr int kMaxDepth = 32;
void removeTreeAt(int parent_fd, const char* name, int depth) {
  if (::unlinkat(parent_fd, name, 0) == 0 || depth > kMaxDepth) return;
  const int fd = ::openat(parent_fd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  alignas(8) char buffer[2048];
  for (int pass = 0; pass < 4 && ::unlinkat(parent_fd, name, AT_REMOVEDIR) != 0; ++pass) {
    ::lseek(fd, 0, SEEK_SET);
    ssize_t n = 0;
    while ((n = ::getdents64(fd, buffer, sizeof(buffer))) > 0) {
      for (ssize_t at = 0; at < n;) {
        const auto* entry = reinterpret_cast<const struct dirent64*>(buffer + at);
        at += entry->d_reclen;
        const char* child = entry->d_name;
        if (child[0] == '.' && (child[1] == '\0' || (child[1] == '.' && child[2] == '\0'))) {
          continue;
        }
        removeTreeAt(fd, child, depth + 1);
      }
    }
  }
  ::close(fd);
}

extern "C" void removeTemporariesAndDie(int signal_number) {
  for (TemporarySlot& slot : g_temporaries) {
    if (slot.used.load(std::memory_order_acquire)) removeTreeAt(AT_FDCWD, slot.path, 0);
  }
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
}

void installHandlers() {
  for (int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction current {};
    if (::sigaction(signal_number, nullptr, &current) != 0) continue;
    if (current.sa_handler != SIG_DFL) continue;  // ignored (nohup) or owned by someone else
    struct sigaction action {};
    action.sa_handler = removeTemporariesAndDie;
    sigemptyset(&action.sa_mask);
    ::sigaction(signal_number, &action, nullptr);
  }
}

fs::path temporaryFor(const fs::path& final_path) {
  fs::path temp = final_path;
  temp += kTemporaryInfix + std::to_string(::getpid());
  return temp;
}

// The pid of a single-file temporary's name ("<name>.gtbake-tmp-<pid>"), or -1.
long temporaryPid(const std::string& name) {
  const std::size_t at = name.rfind(kTemporaryInfix);
  if (at == std::string::npos || at == 0) return -1;
  const std::string digits = name.substr(at + std::strlen(kTemporaryInfix));
  if (digits.empty() || digits.size() > 9 ||
      digits.find_first_not_of("0123456789") != std::string::npos) {
    return -1;
  }
  return std::stol(digits);
}

const char* specialFileKind(const fs::file_status& status) {
  switch (status.type()) {
    case fs::file_type::fifo:
      return "a FIFO (named pipe)";
    case fs::file_type::socket:
      return "a socket";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::block:
      return "a block device";
    default:
      return nullptr;
  }
}

}  // namespace

int registerTemporary(const fs::path& path) {
  std::call_once(g_handlers_installed, installHandlers);
  const std::string text = fs::absolute(path).string();
  if (text.size() >= kSlotPathBytes) return -1;
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  for (int i = 0; i < kTemporarySlots; ++i) {
    TemporarySlot& slot = g_temporaries[static_cast<std::size_t>(i)];
    if (!slot.used.load(std::memory_order_relaxed)) {
      std::memcpy(slot.path, text.c_str(), text.size() + 1);
      slot.used.store(true, std::memory_order_release);
      return i;
    }
  }
  return -1;
}

void unregisterTemporary(int slot) {
  if (slot < 0 || slot >= kTemporarySlots) return;
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  g_temporaries[static_cast<std::size_t>(slot)].used.store(false, std::memory_order_release);
}

AtomicOutput::AtomicOutput(fs::path final_path)
    : final_(std::move(final_path)), temp_(temporaryFor(final_)) {
  refuseSpecialFile(final_, "output");
  slot_ = registerTemporary(temp_);
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove(temp_, ignored);
  }
  unregisterTemporary(slot_);
}

void AtomicOutput::commit() {
  std::error_code ec;
  if (!fs::exists(temp_, ec)) {
    throw Error("internal: nothing was written to " + temp_.string());
  }
  fs::rename(temp_, final_, ec);
  if (ec) throw Error("cannot write " + final_.string() + ": " + ec.message());
  committed_ = true;
}

void writeBytesChecked(const fs::path& path, std::string_view bytes, const fs::path& name) {
  const std::string where = "cannot write " + name.string() + ": ";
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw Error(where + std::strerror(errno));
  const char* inject = std::getenv("GTBAKE_TEST_FAIL_WRITE");
  const bool fail = inject != nullptr && *inject != '\0' &&
                    name.filename().string().find(inject) != std::string::npos;
  std::size_t done = 0;
  int error = 0;
  const std::size_t limit = fail ? bytes.size() / 2 : bytes.size();
  while (done < limit) {
    const ssize_t n = ::write(fd, bytes.data() + done, limit - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n < 0 ? errno : ENOSPC;
      break;
    }
    done += static_cast<std::size_t>(n);
  }
  if (error == 0 && fail) error = ENOSPC;
  if (error == 0 && ::fsync(fd) != 0 && errno != EINVAL) error = errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) {
    throw Error(where + std::strerror(error) +
                (fail ? " (injected by GTBAKE_TEST_FAIL_WRITE)" : ""));
  }
}

void writeFileAtomically(const fs::path& path, std::string_view bytes) {
  AtomicOutput output(path);
  writeBytesChecked(output.tempPath(), bytes, path);
  output.commit();
}

void refuseSpecialFile(const fs::path& path, const std::string& what) {
  std::error_code ec;
  const char* kind = specialFileKind(fs::status(path, ec));
  if (kind == nullptr) return;
  throw Error(what + " " + path.string() + " is " + kind +
              ", not a file or directory gtbake may replace; name another path");
}

void syncDirectory(const fs::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) throw Error("cannot open " + dir.string() + ": " + std::strerror(errno));
  const int result = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  if (result != 0 && error != EINVAL) {
    throw Error("cannot sync " + dir.string() + ": " + std::strerror(error));
  }
}

bool processIsRunning(long pid) {
  if (pid <= 0) return false;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

void testKillPoint(const char* point) {
  const char* at = std::getenv("GTBAKE_TEST_KILL_AT");
  if (at != nullptr && std::strcmp(at, point) == 0) ::raise(SIGKILL);
}

void ensureDirectory(const fs::path& dir) {
  std::error_code ec;
  if (fs::is_directory(dir, ec)) return;
  refuseSpecialFile(dir, "output directory");
  if (fs::exists(dir, ec)) throw Error(dir.string() + " exists and is not a directory");
  fs::create_directories(dir, ec);
  if (ec) throw Error("cannot create directory " + dir.string() + ": " + ec.message());
}

std::string relativePath(const fs::path& path, const fs::path& base) {
  const fs::path relative = fs::absolute(path).lexically_relative(fs::absolute(base));
  return relative.empty() ? "." : relative.string();
}

std::string readFile(const fs::path& path) {
  return readRegularFile(path);
}

std::vector<fs::path> cleanStaleTemporaries(const fs::path& dir) {
  std::vector<fs::path> removed;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const long pid = temporaryPid(entry.path().filename().string());
    std::error_code type_error;
    if (pid < 0 || !entry.is_regular_file(type_error) || entry.is_symlink(type_error)) continue;
    if (pid == static_cast<long>(::getpid())) continue;
    if (processIsRunning(pid)) {
      std::fprintf(stderr, "gtbake: note: leaving %s (process %ld is still running)\n",
                   entry.path().c_str(), pid);
      continue;
    }
    std::error_code remove_error;
    fs::remove(entry.path(), remove_error);
    if (!remove_error) {
      std::fprintf(stderr, "gtbake: note: removed %s left by an interrupted run\n",
                   entry.path().c_str());
      removed.push_back(entry.path());
    }
  }
  return removed;
}

bool isStaleTemporary(const fs::path& path) {
  const long pid = temporaryPid(path.filename().string());
  return pid >= 0 && pid != static_cast<long>(::getpid()) && !processIsRunning(pid);
}

}  // namespace gtbake
