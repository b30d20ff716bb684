#include "common/output_stage.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <system_error>
#include <vector>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/input_limits.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStageInfix = ".gtbake-stage-";
constexpr const char* kMarkerName = "gtbake-stage.json";
constexpr const char* kTool = "gtbake";
std::atomic<int> g_stage_counter{0};

// The pid in a stage directory's name, or -1 if the name is not one.
long stagePid(const std::string& name) {
  const std::size_t at = name.rfind(kStageInfix);
  if (name.empty() || name[0] != '.' || at == std::string::npos || at < 2) return -1;
  const std::string rest = name.substr(at + std::strlen(kStageInfix));
  const std::size_t dash = rest.find('-');
  if (dash == std::string::npos || dash == 0 || dash > 9 || dash + 1 == rest.size()) return -1;
  const std::string pid = rest.substr(0, dash);
  const std::string n = rest.substr(dash + 1);
  if (pid.find_first_not_of("0123456789") != std::string::npos ||
      n.find_first_not_of("0123456789") != std::string::npos) {
    return -1;
  }
  return std::stol(pid);
}

// Field 22 of /proc/<pid>/stat (clock ticks since boot), or "" if unknown: with the pid it
// names one process, so a reused pid is told apart.
std::string processStartTime(long pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");  // size 0: read as a stream
  std::string stat;
  std::getline(in, stat);
  std::size_t at = stat.rfind(')');
  if (at == std::string::npos) return "";
  for (int field = 2; field < 22 && at != std::string::npos; ++field) at = stat.find(' ', at + 1);
  if (at == std::string::npos) return "";
  const std::size_t end = stat.find(' ', at + 1);
  return stat.substr(at + 1, end == std::string::npos ? std::string::npos : end - at - 1);
}

enum class StageOwner { kNone, kThisProcess, kStale, kOther };

StageOwner stageOwner(const fs::path& stage) {
  const long name_pid = stagePid(stage.filename().string());
  if (name_pid < 0) return StageOwner::kNone;
  std::error_code ec;
  if (!fs::exists(stage / kMarkerName, ec)) {
    const bool dead_and_empty = fs::is_empty(stage, ec) && !ec && !processIsRunning(name_pid);
    return dead_and_empty ? StageOwner::kStale : StageOwner::kNone;
  }
  try {
    const nlohmann::json marker = nlohmann::json::parse(readRegularFile(stage / kMarkerName));
    if (marker.at("tool") != kTool || marker.at("pid").get<long>() != name_pid) {
      return StageOwner::kNone;
    }
    const std::string start = marker.at("start").get<std::string>();
    if (name_pid == static_cast<long>(::getpid())) {
      return start == processStartTime(name_pid) ? StageOwner::kThisProcess : StageOwner::kStale;
    }
    if (!processIsRunning(name_pid)) return StageOwner::kStale;
    const std::string now = processStartTime(name_pid);
    return !now.empty() && !start.empty() && now != start ? StageOwner::kStale : StageOwner::kOther;
  } catch (const std::exception&) {
    return StageOwner::kNone;  // not a marker we wrote: the user's
  }
}

void makeDirectoryLike(const fs::path& path, const fs::path& like) {
  std::error_code ec;
  if (!fs::create_directory(path, ec) && ec) {
    throw Error("cannot create " + path.string() + ": " + ec.message());
  }
  const fs::file_status status = fs::status(like, ec);
  if (!ec) fs::permissions(path, status.permissions(), ec);
}

// `live` brought to `target`: a hard link, or a copy (regular files) when linking fails.
void linkEntry(const fs::path& live, const fs::path& target, const fs::file_status& status) {
  std::error_code ec;
  if (status.type() == fs::file_type::symlink) {
    fs::create_symlink(fs::read_symlink(live, ec), target, ec);
    if (ec) throw Error("cannot copy the symlink " + live.string() + ": " + ec.message());
    return;
  }
  if (::link(live.c_str(), target.c_str()) == 0) return;
  const int link_error = errno;
  if (status.type() != fs::file_type::regular) {
    throw Error("cannot link " + live.string() + " into the new set: " + std::strerror(link_error));
  }
  fs::copy_file(live, target, ec);
  if (ec) throw Error("cannot copy " + live.string() + " into the new set: " + ec.message());
  const int fd = ::open(target.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || ::fsync(fd) != 0) {
    const int error = errno;
    if (fd >= 0) ::close(fd);
    throw Error("cannot sync " + target.string() + ": " + std::strerror(error));
  }
  ::close(fd);
}

using LeaveOut = std::function<bool(const fs::path&, const std::string&)>;

void replicateInto(const fs::path& live_dir, const fs::path& tree_dir, const std::string& prefix,
                   const LeaveOut& leave_out) {
  std::error_code ec;
  std::vector<fs::directory_entry> entries;
  for (const auto& entry : fs::directory_iterator(live_dir, ec)) entries.push_back(entry);
  if (ec) throw Error("cannot list " + live_dir.string() + ": " + ec.message());
  for (const fs::directory_entry& entry : entries) {
    const std::string name = entry.path().filename().string();
    const std::string relative = prefix + name;
    if (leave_out(entry.path(), relative)) continue;
    const fs::file_status status = fs::symlink_status(entry.path(), ec);
    if (ec) continue;  // gone meanwhile
    const fs::path target = tree_dir / name;
    const fs::file_status present = fs::symlink_status(target, ec);
    if (status.type() == fs::file_type::directory) {
      const StageOwner owner = stageOwner(entry.path());
      if (owner == StageOwner::kThisProcess) {
        fs::rename(entry.path(), target, ec);  // a set of this process still staging inside
        if (ec) throw Error("cannot move " + entry.path().string() + ": " + ec.message());
        continue;
      }
      if (owner != StageOwner::kNone) continue;  // another run's stage: never part of a set
      if (present.type() == fs::file_type::not_found) makeDirectoryLike(target, entry.path());
      if (fs::is_directory(fs::symlink_status(target, ec))) {
        replicateInto(entry.path(), target, relative + "/", leave_out);
      }
      continue;
    }
    if (present.type() == fs::file_type::not_found) linkEntry(entry.path(), target, status);
  }
}

void syncTree(const fs::path& dir) {
  syncDirectory(dir);
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::error_code type_error;
    if (entry.is_directory(type_error) && !entry.is_symlink(type_error)) syncTree(entry.path());
  }
}

}  // namespace

bool isStageDirectoryName(const std::string& name) {
  return stagePid(name) >= 0;
}

StagedDirectory::StagedDirectory(const fs::path& real_dir) : dir_(real_dir) {
  const long pid = static_cast<long>(::getpid());
  std::error_code ec;
  do {  // a name already taken (a stale stage of an earlier process with this pid) is skipped
    container_ =
        dir_.parent_path() / ("." + dir_.filename().string() + kStageInfix + std::to_string(pid) +
                              "-" + std::to_string(g_stage_counter.fetch_add(1)));
  } while (!fs::create_directory(container_, ec) && !ec);
  if (ec) {
    throw Error("cannot stage the output set of " + dir_.string() + ": cannot create " +
                container_.string() + ": " + ec.message() +
                " (the new set is assembled beside the directory, so its parent must be "
                "writable)");
  }
  slot_ = registerTemporary(container_);
  nlohmann::ordered_json marker;
  marker["tool"] = kTool;
  marker["pid"] = pid;
  marker["start"] = processStartTime(pid);
  marker["dir"] = dir_.string();
  writeBytesChecked(container_ / kMarkerName, marker.dump() + "\n", container_ / kMarkerName);
  tree_ = container_ / "tree";
  makeDirectoryLike(tree_, dir_);
}

StagedDirectory::~StagedDirectory() {
  std::error_code ignored;
  fs::remove_all(container_, ignored);
  unregisterTemporary(slot_);
}

void StagedDirectory::replicate(const LeaveOut& leave_out) {
  replicateInto(dir_, tree_, "", leave_out);
}

void StagedDirectory::sync() const {
  syncTree(tree_);
  syncDirectory(container_);
}

void StagedDirectory::switchIn() {
  std::error_code ec;
  // A working directory inside the directory would be left in the old tree: follow the switch.
  const fs::path cwd = fs::current_path(ec);
  const fs::path inside = ec ? fs::path() : cwd.lexically_relative(dir_);
  const bool follow = !inside.empty() && *inside.begin() != "..";
  int result = ::renameat2(AT_FDCWD, tree_.c_str(), AT_FDCWD, dir_.c_str(), RENAME_EXCHANGE);
  if (result != 0 && errno == ENOENT && !fs::exists(fs::symlink_status(dir_, ec))) {
    result = ::renameat2(AT_FDCWD, tree_.c_str(), AT_FDCWD, dir_.c_str(), RENAME_NOREPLACE);
  }
  if (result != 0) {
    throw Error("cannot switch the new output set into " + dir_.string() + ": " +
                std::strerror(errno) + " (the previous set is untouched)");
  }
  testKillPoint("commit-exchanged");
  if (follow && ::chdir(cwd.c_str()) != 0) {
    throw Error("cannot enter " + cwd.string() +
                " again after switching it: " + std::strerror(errno));
  }
  syncDirectory(dir_.parent_path());
  fs::remove_all(container_, ec);
  if (ec) {
    std::fprintf(stderr, "gtbake: note: cannot remove the previous set in %s: %s\n",
                 container_.c_str(), ec.message().c_str());
  }
}

void checkSwitchable(const fs::path& real_dir, const fs::path& shown) {
  struct statx info {};
  struct stat self {};
  struct stat parent {};
  const bool mount_root =
      (::statx(AT_FDCWD, real_dir.c_str(), AT_SYMLINK_NOFOLLOW, STATX_BASIC_STATS, &info) == 0 &&
       (info.stx_attributes_mask & STATX_ATTR_MOUNT_ROOT) != 0)
          ? (info.stx_attributes & STATX_ATTR_MOUNT_ROOT) != 0
          : ::stat(real_dir.c_str(), &self) == 0 &&
                ::stat(real_dir.parent_path().c_str(), &parent) == 0 &&
                self.st_dev != parent.st_dev;
  if (mount_root) {
    throw Error(shown.string() + " is a mount point: gtbake switches an output directory whole " +
                "by exchanging it with a new one staged beside it, which cannot cross a mount; " +
                "write into a directory inside it (e.g. " + (shown / "out").string() + ")");
  }
  const StagedDirectory probe(real_dir);
  const fs::path other = probe.tree().parent_path() / "probe";
  makeDirectoryLike(other, probe.tree());
  if (::renameat2(AT_FDCWD, probe.tree().c_str(), AT_FDCWD, other.c_str(), RENAME_EXCHANGE) != 0) {
    throw Error("the file system of " + shown.string() + " cannot exchange two directories (" +
                std::strerror(errno) + "), which output sets need to switch whole: write to a " +
                "local file system (ext4, xfs, btrfs, tmpfs)");
  }
}

void cleanStaleStages(const fs::path& real_dir) {
  const std::string prefix = "." + real_dir.filename().string() + kStageInfix;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(real_dir.parent_path(), ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || stagePid(name) < 0) continue;
    if (stageOwner(entry.path()) != StageOwner::kStale) continue;
    std::error_code remove_error;
    fs::remove_all(entry.path(), remove_error);
    if (!remove_error) {
      std::fprintf(stderr, "gtbake: note: removed %s left by an interrupted run\n",
                   entry.path().c_str());
    }
  }
}

}  // namespace gtbake
