// Runs the built gtbake binary as a user would and captures what it prints.
#pragma once

#include <string>

#include "support/temp_dir.h"

namespace gtbake::test {

struct RunResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// Runs `gtbake <arguments>` through /bin/sh (arguments are passed as written) with no stdin.
RunResult runGtbake(const std::string& arguments);

}  // namespace gtbake::test
