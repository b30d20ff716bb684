#include "common/atomic_file.h"

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

extern "C" void removeTemporariesAndDie(int signal_number) {
  for (TemporarySlot& slot : g_temporaries) {
    if (slot.used.load(std::memory_order_acquire)) {
      if (::unlink(slot.path) != 0) ::rmdir(slot.path);
    }
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
  temp += ".tmp-" + std::to_string(::getpid());
  return temp;
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

void ensureDirectory(const fs::path& dir) {
  std::error_code ec;
  if (fs::is_directory(dir, ec)) return;
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
    const std::string name = entry.path().filename().string();
    const std::size_t at = name.rfind(".tmp-");
    if (at == std::string::npos) continue;
    const std::string digits = name.substr(at + 5);
    if (digits.empty() || digits.size() > 9 ||
        digits.find_first_not_of("0123456789") != std::string::npos) {
      continue;
    }
    const long pid = std::stol(digits);
    if (pid == static_cast<long>(::getpid())) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM) {
      std::fprintf(stderr, "gtbake: note: leaving %s (process %ld is still running)\n",
                   entry.path().c_str(), pid);
      continue;
    }
    std::error_code remove_error;
    fs::remove_all(entry.path(), remove_error);
    if (!remove_error) {
      std::fprintf(stderr, "gtbake: note: removed %s left by an interrupted run\n",
                   entry.path().c_str());
      removed.push_back(entry.path());
    }
  }
  return removed;
}

}  // namespace gtbake
