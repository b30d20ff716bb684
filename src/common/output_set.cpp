#include "common/output_set.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <set>
#include <system_error>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/input_limits.h"
#include "common/output_lock.h"
#include "common/output_stage.h"
#include "common/sha256.h"
#include "gtbake_version.h"

namespace gtbake {

namespace fs = std::filesystem;

std::string manifestFileName(const std::string& command) {
  return command + ".manifest.json";
}

namespace {

// The command line that writes the set named `command` ("validate_gtso" -> "validate-gtso"), for
// the "rerun" advice of the errors.
std::string rerun(const std::string& command) {
  if (command == "shard") return "gtbake sweep --shard";
  if (command == "fit_report") return "gtbake fit";
  std::string name = command;
  std::replace(name.begin(), name.end(), '_', '-');
  return "gtbake " + name;
}

// A manifest of this gtbake version for `command` in `dir`, with no files yet.
OutputManifest emptyManifest(const fs::path& dir, const std::string& command,
                             nlohmann::ordered_json settings) {
  OutputManifest manifest;
  manifest.dir = dir;
  manifest.command = command;
  manifest.gtbake_version = GTBAKE_VERSION;
  manifest.settings = std::move(settings);
  return manifest;
}

// The text of <command>.manifest.json: command, version, settings, then every file's name, size
// and SHA-256 (the layout readOutputSet parses).
std::string manifestText(const OutputManifest& manifest) {
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const OutputFile& f : manifest.files) {
    files.push_back({{"name", f.name}, {"size", f.size}, {"sha256", f.sha256}});
  }
  nlohmann::ordered_json doc;
  doc["command"] = manifest.command;
  doc["gtbake_version"] = manifest.gtbake_version;
  doc["settings"] = manifest.settings;
  doc["files"] = std::move(files);
  return doc.dump(2) + "\n";
}

// The names of the previous set of `command` in `real_dir` and its manifest (what a commit leaves
// out of the new tree), relative to the directory.
std::set<std::string> previousSet(const fs::path& real_dir, const std::string& command) {
  std::set<std::string> names;
  for (const fs::path& path : outputSetPaths(real_dir, command)) {
    names.insert(path.lexically_relative(real_dir).generic_string());
  }
  return names;
}

}  // namespace

const OutputFile* OutputManifest::find(const std::string& name) const {
  for (const OutputFile& f : files) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

namespace {

// The set's entry for `name`; throws if the set has none.
const OutputFile& requireEntry(const OutputManifest& m, const std::string& name) {
  const OutputFile* entry = m.find(name);
  if (entry == nullptr) {
    throw Error((m.dir / name).string() + " is not part of the output set in " +
                (m.dir / manifestFileName(m.command)).string() + " (rerun `" + rerun(m.command) +
                "`)");
  }
  return *entry;
}

[[noreturn]] void throwMismatch(const OutputManifest& m, const std::string& name,
                                std::uint64_t size, const OutputFile& entry) {
  throw Error((m.dir / name).string() + " does not match " + manifestFileName(m.command) + " (" +
              std::to_string(size) + " bytes, manifest says " + std::to_string(entry.size) +
              " and another SHA-256): it was changed or replaced after `" + rerun(m.command) +
              "` wrote it; rerun that command");
}

}  // namespace

void OutputManifest::verify(const std::string& name, std::string_view bytes) const {
  const OutputFile& entry = requireEntry(*this, name);
  if (entry.size != bytes.size() || entry.sha256 != sha256Hex(bytes)) {
    throwMismatch(*this, name, bytes.size(), entry);
  }
}

std::string OutputManifest::readVerified(const std::string& name) const {
  const fs::path path = fileInsideDirectory(dir, name, (dir / manifestFileName(command)).string());
  const OutputFile& entry = requireEntry(*this, name);
  // A file of another size is refused before it is read (docs/limits.md §Output sets), and
  // the read is bounded by the recorded size in case it grows meanwhile.
  std::error_code ec;
  const std::uintmax_t size = fs::is_regular_file(path, ec) ? fs::file_size(path, ec) : 0;
  if (!ec && fs::is_regular_file(path, ec) && size != entry.size) {
    throwMismatch(*this, name, size, entry);
  }
  std::string bytes = readRegularFile(path, entry.size);
  verify(name, bytes);
  return bytes;
}

nlohmann::json OutputManifest::readVerifiedJson(const std::string& name) const {
  const std::filesystem::path path = dir / name;
  try {
    return parseJsonText(readVerified(name), path.string());
  } catch (const Error& e) {
    const std::string what = e.what();
    if (what.find("malformed JSON") == std::string::npos) throw;
    throw Error(path.string() + ": not valid JSON (" + what + ")");
  }
}

OutputSet::OutputSet(fs::path dir, std::string command)
    : dir_(std::move(dir)), command_(std::move(command)) {
  lock_ = std::make_unique<OutputLock>(dir_);
  ensureDirectory(lock_->realDir());
  stage_ = std::make_unique<StagedDirectory>(lock_->realDir());
}

OutputSet::~OutputSet() = default;

fs::path OutputSet::checkName(const std::string& name) const {
  if (committed_) throw Error("internal: output set " + dir_.string() + " already committed");
  const fs::path final_path = fileInsideDirectory(dir_, name, "output set " + dir_.string());
  for (const Staged& s : staged_) {
    if (s.file.name == name) throw Error("internal: " + final_path.string() + " written twice");
  }
  if (name == manifestFileName(command_)) {
    throw Error("internal: " + name + " is the manifest's own name");
  }
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(final_path, ec))) {
    throw Error("cannot write " + final_path.string() + ": a directory of that name is in the way");
  }
  for (fs::path up = fs::path(name).parent_path(); !up.empty(); up = up.parent_path()) {
    const fs::file_status status = fs::symlink_status(dir_ / up, ec);
    if (fs::exists(status) && !fs::is_directory(status)) {
      throw Error("cannot write " + final_path.string() + ": " + (dir_ / up).string() +
                  " is in the way and is not a directory");
    }
  }
  return final_path;
}

void OutputSet::add(const std::string& name, std::string_view bytes) {
  const fs::path final_path = checkName(name);
  const fs::path staged = stage_->tree() / name;
  if (fs::path(name).has_parent_path()) ensureDirectory(staged.parent_path());
  staged_.push_back({{name, bytes.size(), sha256Hex(bytes)}, false});
  writeBytesChecked(staged, bytes, final_path);
}

void OutputSet::adopt(const std::string& name) {
  checkName(name);
  staged_.push_back({{name, 0, ""}, true});
}

OutputManifest OutputSet::commit() {
  const fs::path& real = lock_->realDir();
  const NestedLocks nested(real);  // writers inside the directory finish first
  testKillPoint("commit-start");
  for (Staged& s : staged_) {
    if (!s.adopted) continue;
    const fs::path staged = stage_->tree() / s.file.name;
    ensureDirectory(staged.parent_path());
    const fs::path live = fileInsideDirectory(real, s.file.name, "output set " + dir_.string());
    if (::link(live.c_str(), staged.c_str()) != 0) {
      throw Error("cannot add " + (dir_ / s.file.name).string() +
                  " to the output set: " + std::strerror(errno));
    }
    const std::string bytes = readRegularFile(staged);
    s.file.size = bytes.size();
    s.file.sha256 = sha256Hex(bytes);
  }
  const std::set<std::string> previous = previousSet(real, command_);
  stage_->replicate([&](const fs::path& live, const std::string& relative) {
    return previous.count(relative) != 0 || nested.took(live) || isStaleTemporary(live);
  });
  testKillPoint("commit-linked");
  OutputManifest manifest = emptyManifest(dir_, command_, settings_);
  for (const Staged& s : staged_) manifest.files.push_back(s.file);
  const std::string name = manifestFileName(command_);
  writeBytesChecked(stage_->tree() / name, manifestText(manifest), dir_ / name);
  testKillPoint("commit-manifest");
  stage_->sync();
  testKillPoint("commit-synced");
  stage_->switchIn();
  committed_ = true;
  testKillPoint("commit-done");
  return manifest;
}

OutputManifest readOutputSet(const fs::path& dir, const std::string& command) {
  const fs::path path = dir / manifestFileName(command);
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    throw Error(dir.string() + " has no complete `" + rerun(command) + "` output (no " +
                manifestFileName(command) + "; the run was interrupted or failed, or the files " +
                "come from elsewhere): rerun `" + rerun(command) + "`");
  }
  const nlohmann::json doc = readJsonFile(path);
  const std::string where = path.string();
  if (!doc.is_object() || !doc.contains("command") || !doc["command"].is_string() ||
      !doc.contains("files") || !doc["files"].is_array() || !doc.contains("gtbake_version") ||
      !doc["gtbake_version"].is_string()) {
    throw Error(where + ": not an output-set manifest (needs command, gtbake_version, files)");
  }
  OutputManifest manifest;
  manifest.dir = dir;
  manifest.command = doc["command"].get<std::string>();
  if (manifest.command != command) {
    throw Error(where + ": written by `" + rerun(manifest.command) + "`, expected `" +
                rerun(command) + "`");
  }
  manifest.gtbake_version = doc["gtbake_version"].get<std::string>();
  if (doc.contains("settings")) manifest.settings = doc["settings"];
  for (const nlohmann::json& f : doc["files"]) {
    if (!f.is_object() || !f.contains("name") || !f["name"].is_string() || !f.contains("sha256") ||
        !f["sha256"].is_string() || f["sha256"].get<std::string>().size() != 64) {
      throw Error(where + ": every file entry needs a name, a size and a SHA-256");
    }
    OutputFile file;
    file.name = f["name"].get<std::string>();
    fileInsideDirectory(dir, file.name, where);
    file.size = static_cast<std::uint64_t>(jsonInteger(f, "size", 0, INT64_MAX, where));
    file.sha256 = f["sha256"].get<std::string>();
    if (manifest.find(file.name) != nullptr) {
      throw Error(where + ": lists " + file.name + " twice");
    }
    manifest.files.push_back(file);
  }
  return manifest;
}

OutputManifest sealOutputSet(const fs::path& dir, const std::string& command,
                             const std::vector<std::string>& names,
                             nlohmann::ordered_json settings) {
  OutputSet set(dir, command);
  for (const std::string& name : names) set.adopt(name);
  set.setSettings(std::move(settings));
  return set.commit();
}

OutputManifest resealOutputSet(const fs::path& dir, const std::string& command) {
  const OutputManifest old = readOutputSet(dir, command);
  std::vector<std::string> names;
  for (const OutputFile& f : old.files) names.push_back(f.name);
  return sealOutputSet(dir, command, names, old.settings);
}

std::vector<fs::path> outputSetPaths(const fs::path& dir, const std::string& command) {
  std::vector<fs::path> paths;
  std::error_code ec;
  if (!fs::is_regular_file(dir / manifestFileName(command), ec)) return paths;
  paths.push_back(dir / manifestFileName(command));
  try {
    for (const OutputFile& f : readOutputSet(dir, command).files) paths.push_back(dir / f.name);
  } catch (const Error&) {
    // A broken manifest is reported by the reader; the manifest itself is still an input.
  }
  return paths;
}

void verifyOutputSet(const OutputManifest& manifest) {
  for (const OutputFile& f : manifest.files) manifest.readVerified(f.name);
}

bool sameOrInside(const fs::path& candidate, const fs::path& input) {
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(fs::absolute(candidate), ec);
  if (ec) return false;
  const fs::path b = fs::weakly_canonical(fs::absolute(input), ec);
  if (ec) return false;
  if (a == b) return true;
  const fs::path relative = b.lexically_relative(a);
  return !relative.empty() && *relative.begin() != "..";
}

}  // namespace gtbake

namespace gtbake {

void checkOutputFile(const fs::path& out, const std::string& option,
                     const std::vector<fs::path>& inputs) {
  refuseSpecialFile(out, option);
  std::error_code ec;
  if (fs::is_directory(out, ec) || out.filename().empty() || out.filename() == "." ||
      out.filename() == "..") {
    throw Error(option + " " + out.string() + " is a directory; name the file to write");
  }
  for (const fs::path& input : inputs) {
    if (sameOrInside(out, input)) {
      throw Error(option + " " + out.string() + " would overwrite the input " + input.string() +
                  "; write it somewhere else");
    }
  }
}

}  // namespace gtbake
