#include "cli_harness.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace gtbake::test {

namespace fs = std::filesystem;

TempDir::TempDir(const std::string& tag) {
  path_ = fs::temp_directory_path() / ("gtbake-" + tag + "-" + std::to_string(::getpid()));
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
}

std::string readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

RunResult runGtbake(const std::string& arguments) {
  const TempDir capture("capture");
  const fs::path out = capture.path() / "stdout";
  const fs::path err = capture.path() / "stderr";
  const std::string command = std::string(GTBAKE_BINARY) + " " + arguments + " </dev/null >" +
                              out.string() + " 2>" + err.string();
  const int status = std::system(command.c_str());
  RunResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = readBytes(out);
  result.err = readBytes(err);
  return result;
}

}  // namespace gtbake::test
