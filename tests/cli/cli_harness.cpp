#include "cli_harness.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>

namespace gtbake::test {

namespace fs = std::filesystem;

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
