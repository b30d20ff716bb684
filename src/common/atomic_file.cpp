#include "common/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include "common/error.h"

namespace gtbake {

namespace fs = std::filesystem;

AtomicOutput::AtomicOutput(fs::path final_path) : final_(std::move(final_path)) {
  temp_ = final_;
  temp_ += ".tmp-" + std::to_string(::getpid());
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove(temp_, ignored);
  }
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

void writeFileAtomically(const fs::path& path, std::string_view bytes) {
  writeAtomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error("cannot write " + path.string() + ": " + std::strerror(errno));
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw Error("cannot write " + path.string() + ": write failed (disk full?)");
  });
}

void writeAtomically(const fs::path& path, const std::function<void(const fs::path&)>& writer) {
  AtomicOutput output(path);
  writer(output.tempPath());
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
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw Error("no such file: " + path.string());
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read " + path.string() + ": " + std::strerror(errno));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace gtbake
