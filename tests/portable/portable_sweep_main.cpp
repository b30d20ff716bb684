// `gtbake sweep` linked against the portable build of the sweep (tests/portable/CMakeLists.txt):
//   portable_sweep OUT SPP WIDTH HEIGHT THREADS SCENE...
#include <cstdio>
#include <exception>
#include <string>

#include "sweep/sweep_command.h"

int main(int argc, char** argv) {
  if (argc < 7) {
    std::fprintf(stderr, "usage: portable_sweep OUT SPP WIDTH HEIGHT THREADS SCENE...\n");
    return 2;
  }
  try {
    gtbake::SweepOptions options;
    options.out = argv[1];
    options.spp = std::stoi(argv[2]);
    options.width = std::stoi(argv[3]);
    options.height = std::stoi(argv[4]);
    options.threads = std::stoi(argv[5]);
    for (int i = 6; i < argc; ++i) options.scenes.emplace_back(argv[i]);
    options.progress = false;
    gtbake::runSweep(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "portable_sweep: %s\n", e.what());
    return 1;
  }
  return 0;
}
