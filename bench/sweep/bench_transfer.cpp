// Cost of the transfer channels (docs/sweep.md, "Transfer"; docs/lighting.md §5): the same sweep
// with --transfer off and on, alternating, best of `repeats` each, in one run; prints wall and
// CPU seconds, their ratio (the bar: ≤ 1.3) and the EXR bytes of both.
//
// Usage: bench_transfer SCENES OUT_DIR [threads = all] [res = 128] [spp = 84] [repeats = 2]
// (the defaults are the corpus sweep of `gtbake all`, docs/sweep.md §7).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <string>

#include "sweep/sweep_command.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

struct Timing {
  double wall = 1e30;  // seconds, best
  double cpu = 1e30;   // CPU seconds of the process, best
};

// Sum of the sizes of the *.exr files of a directory.
std::uintmax_t exrBytes(const fs::path& dir) {
  std::uintmax_t bytes = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == ".exr") bytes += entry.file_size();
  }
  return bytes;
}

void timeOnce(const SweepOptions& o, Timing* best) {
  const std::clock_t cpu0 = std::clock();
  const auto wall0 = std::chrono::steady_clock::now();
  runSweep(o);
  best->wall = std::min(
      best->wall, std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count());
  best->cpu = std::min(best->cpu, static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC);
}

int run(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_transfer SCENES OUT_DIR [threads] [res] [spp] [repeats]\n");
    return 2;
  }
  SweepOptions o;
  o.scenes = {argv[1]};
  o.threads = argc > 3 ? std::atoi(argv[3]) : 0;
  o.width = o.height = argc > 4 ? std::atoi(argv[4]) : 128;
  o.spp = argc > 5 ? std::atoi(argv[5]) : 84;
  o.specular_spp = 14;
  o.progress = false;
  const int repeats = argc > 6 ? std::atoi(argv[6]) : 2;
  Timing off;
  Timing on;
  SweepOptions without = o;
  without.transfer = false;
  without.out = fs::path(argv[2]) / "off";
  SweepOptions with = o;
  with.out = fs::path(argv[2]) / "on";
  for (int r = 0; r < repeats; ++r) {
    timeOnce(without, &off);
    timeOnce(with, &on);
  }
  const double off_bytes = static_cast<double>(exrBytes(without.out));
  const double on_bytes = static_cast<double>(exrBytes(with.out));
  std::printf("transfer off: %.2f s wall, %.2f CPU-s; EXR %.2f MB\n", off.wall, off.cpu,
              off_bytes / 1e6);
  std::printf("transfer on:  %.2f s wall, %.2f CPU-s; EXR %.2f MB\n", on.wall, on.cpu,
              on_bytes / 1e6);
  std::printf("ratio on/off: %.3f wall, %.3f CPU (bar 1.3); EXR x%.3f\n", on.wall / off.wall,
              on.cpu / off.cpu, on_bytes / off_bytes);
  return on.cpu / off.cpu <= 1.3 ? 0 : 1;
}

}  // namespace
}  // namespace gtbake

int main(int argc, char** argv) {
  return gtbake::run(argc, argv);
}
