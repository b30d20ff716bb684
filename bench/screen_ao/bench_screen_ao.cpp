// bench_screen_ao: seconds per megapixel of every screen-space estimator at its defaults
// (docs/screen_ao.md), wall and CPU time, on the G-buffers of a sweep.
//
//   bench_screen_ao [SWEEP_DIR] [--threads T]
//
// Without SWEEP_DIR it first sweeps data/scenes (or the directory in GTBAKE_SCENES) at 192×192
// with 16 walks per pixel into a temporary directory: the estimators read only Z, N, mask and the
// camera, which do not depend on the walk count.
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "common/threads.h"
#include "screen_ao/gbuffer.h"
#include "screen_ao/screen_ao_settings.h"
#include "sweep/sweep_command.h"

namespace {

namespace fs = std::filesystem;

double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
         1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

fs::path sweepDefaultScenes(int threads) {
  const char* scenes = std::getenv("GTBAKE_SCENES");
  gtbake::SweepOptions o;
  o.scenes = {scenes != nullptr ? fs::path(scenes) : fs::path("data/scenes")};
  o.out = fs::temp_directory_path() / ("gtbake-bench-screen-ao-" + std::to_string(getpid()));
  o.spp = 16;
  o.specular_roughness = {};
  o.threads = threads;
  o.progress = false;
  std::fprintf(stderr, "sweeping %s at 192x192, 16 walks, into %s\n", o.scenes[0].c_str(),
               o.out.c_str());
  gtbake::runSweep(o);
  return o.out;
}

}  // namespace

int main(int argc, char** argv) {
  fs::path sweep;
  int threads = 2;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--threads" && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else {
      sweep = arg;
    }
  }
  try {
    const bool temporary = sweep.empty();
    if (temporary) sweep = sweepDefaultScenes(threads);
    const gtbake::ThreadLimit limit(threads);
    const gtbake::SweepImages images = gtbake::readSweepImages(sweep);
    double megapixels = 0.0;
    for (const auto& image : images.images) megapixels += 1e-6 * image.gbuffer.pixels();
    std::printf("%zu images, %.3f Mpx, %d threads\n", images.images.size(), megapixels,
                limit.threads());
    std::printf("%-16s %9s %9s %9s %9s\n", "estimator", "wall s", "wall s/MP", "cpu s", "cpu s/MP");
    const gtbake::ScreenAoSettings settings;
    for (const std::string& name : gtbake::screenAoEstimatorNames()) {
      const auto start = std::chrono::steady_clock::now();
      const double cpu = cpuSeconds();
      for (const auto& image : images.images) gtbake::runEstimator(settings, name, image.gbuffer);
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double used = cpuSeconds() - cpu;
      std::printf("%-16s %9.2f %9.2f %9.2f %9.2f\n", name.c_str(), wall, wall / megapixels, used,
                  used / megapixels);
      std::fflush(stdout);
    }
    if (temporary) fs::remove_all(sweep);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_screen_ao: %s\n", e.what());
    return 1;
  }
  return 0;
}
