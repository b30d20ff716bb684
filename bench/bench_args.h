// The command line every one-directory benchmark takes: one path (a sweep directory; empty when
// none is given) and `--threads T` (default 2, the machine the figures in docs/ come from).
#pragma once

#include <cstdlib>
#include <string>

namespace gtbake::bench {

struct BenchArgs {
  std::string path;
  int threads = 2;
};

inline BenchArgs parseBenchArgs(int argc, char** argv) {
  BenchArgs args;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--threads" && i + 1 < argc) {
      args.threads = std::atoi(argv[++i]);
    } else {
      args.path = arg;
    }
  }
  return args;
}

}  // namespace gtbake::bench
