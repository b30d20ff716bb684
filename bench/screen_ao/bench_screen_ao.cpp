// bench_screen_ao: seconds per megapixel of every screen-space estimator at its defaults
// (docs/screen_ao.md), wall and CPU time, on the G-buffers of a sweep, with gtao-reference's
// convergence check, each beside a baseline: the seconds per megapixel of a screen_ao.json
// (default luts/screen_ao/screen_ao.json, the committed run) and their ratio; and the estimators'
// total beside the sweep's own seconds (sweep.json /totals/seconds), the stage's bar being 1.5×.
//
//   bench_screen_ao [SWEEP_DIR] [--threads T] [--baseline SCREEN_AO_JSON]
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
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

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

nlohmann::json readJson(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return nlohmann::json();
  return nlohmann::json::parse(in, nullptr, false);
}

// The baseline's seconds per megapixel of `name` (0 if it has none).
double baselineRate(const nlohmann::json& baseline, const std::string& name) {
  const nlohmann::json::json_pointer at("/estimators/" + name + "/seconds_per_megapixel");
  return baseline.is_object() && baseline.contains(at) ? baseline[at].get<double>() : 0.0;
}

struct Timed {
  double wall = 0.0;
  double cpu = 0.0;
};

template <typename F>
Timed timed(F f) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu = cpuSeconds();
  f();
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
          cpuSeconds() - cpu};
}

void printRow(const std::string& name, const Timed& t, double megapixels, double baseline) {
  std::printf("%-16s %9.2f %9.2f %9.2f %9.2f", name.c_str(), t.wall, t.wall / megapixels, t.cpu,
              t.cpu / megapixels);
  if (baseline > 0.0) {
    std::printf(" %11.2f %7.2f\n", baseline, t.wall / megapixels / baseline);
  } else {
    std::printf(" %11s %7s\n", "-", "-");
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  fs::path sweep;
  fs::path baseline_path = "luts/screen_ao/screen_ao.json";
  int threads = 2;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--threads" && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else if (arg == "--baseline" && i + 1 < argc) {
      baseline_path = argv[++i];
    } else {
      sweep = arg;
    }
  }
  try {
    const bool temporary = sweep.empty();
    if (temporary) sweep = sweepDefaultScenes(threads);
    const gtbake::ThreadLimit limit(threads);
    const gtbake::SweepImages images = gtbake::readSweepImages(sweep);
    const nlohmann::json baseline = readJson(baseline_path);
    double megapixels = 0.0;
    std::vector<const gtbake::GBuffer*> gbuffers;
    for (const auto& image : images.images) {
      megapixels += 1e-6 * image.gbuffer.pixels();
      gbuffers.push_back(&image.gbuffer);
    }
    std::printf("%zu images, %.3f Mpx, %d threads; baseline %s\n", images.images.size(), megapixels,
                limit.threads(), baseline.is_object() ? baseline_path.c_str() : "(none)");
    std::printf("%-16s %9s %9s %9s %9s %11s %7s\n", "estimator", "wall s", "wall s/MP", "cpu s",
                "cpu s/MP", "base s/MP", "ratio");
    const gtbake::ScreenAoSettings settings;
    double total = 0.0;
    for (const gtbake::Estimator e : gtbake::screenAoEstimators()) {
      const std::string name = gtbake::describe(e).name;
      const Timed t = timed([&] {
        for (const auto& image : images.images) gtbake::runEstimator(settings, e, image.gbuffer);
      });
      total += t.wall;
      printRow(name, t, megapixels, baselineRate(baseline, name));
    }
    const Timed check = timed([&] { gtbake::referenceConvergence(gbuffers, settings.reference); });
    total += check.wall;
    printRow("convergence", check, megapixels, 0.0);
    const nlohmann::json swept = readJson(sweep / "sweep.json");
    const nlohmann::json::json_pointer seconds("/totals/seconds");
    if (swept.is_object() && swept.contains(seconds)) {
      const double sweep_seconds = swept[seconds].get<double>();
      std::printf("estimators and check %.2f s wall = %.2f x the sweep's %.2f s (bar 1.5x)\n",
                  total, total / sweep_seconds, sweep_seconds);
    }
    if (temporary) fs::remove_all(sweep);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_screen_ao: %s\n", e.what());
    return 1;
  }
  return 0;
}
