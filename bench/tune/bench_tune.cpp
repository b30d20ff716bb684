// bench_tune: the seconds of `gtbake screen-ao` and `gtbake tune` beside the sweep's own seconds
// on a small corpus, in one run (docs/tune.md §7, docs/performance.md): tune as `gtbake tune`
// runs it alone (every estimator's defaults run again) and as `gtbake all` runs it (the defaults
// read from screen-ao's set, --screen-ao), each with its parts (tune.json /provenance/seconds).
//
//   bench_tune [SWEEP_DIR] [--threads T]
//
// Without SWEEP_DIR it first sweeps data/scenes (or the directory in GTBAKE_SCENES) into a
// temporary directory at `gtbake all`'s per-pixel budget (128×128, 84 walks, 14 specular samples,
// docs/scenes.md), so the ratios compare with the stages' in `gtbake all`.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../bench_args.h"
#include "screen_ao/screen_ao_command.h"
#include "sweep/sweep_command.h"
#include "tune/tune_command.h"

namespace {

namespace fs = std::filesystem;

fs::path sweepScenes(const fs::path& out, int threads) {
  const char* scenes = std::getenv("GTBAKE_SCENES");
  gtbake::SweepOptions o;
  o.scenes = {scenes != nullptr ? fs::path(scenes) : fs::path("data/scenes")};
  o.out = out;
  o.width = o.height = 128;
  o.spp = 84;
  o.specular_spp = 14;
  o.threads = threads;
  o.progress = false;
  std::fprintf(stderr, "sweeping %s at 128x128, 84 walks, into %s\n", o.scenes[0].c_str(),
               o.out.c_str());
  gtbake::runSweep(o);
  return o.out;
}

nlohmann::ordered_json readJson(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return nlohmann::ordered_json();
  return nlohmann::ordered_json::parse(in, nullptr, false);
}

void printRow(const std::string& name, double seconds, double sweep_seconds) {
  std::printf("%-40s %9.2f %9.3f\n", name.c_str(), seconds, seconds / sweep_seconds);
  std::fflush(stdout);
}

// tune into <work>/<name>, its total and parts beside the sweep's seconds.
void benchTune(const fs::path& sweep, const fs::path& work, const std::string& name,
               const fs::path& screen_ao, int threads, double sweep_seconds) {
  gtbake::TuneOptions o;
  o.sweep = sweep;
  o.out = work / (screen_ao.empty() ? "tune_alone" : "tune_reuse");
  o.screen_ao = screen_ao;
  o.threads = threads;
  o.progress = false;
  const gtbake::TuneResult r = gtbake::runTune(o);
  printRow("tune, " + name, r.seconds, sweep_seconds);
  const nlohmann::ordered_json tuned = readJson(r.json);
  for (const auto& [part, seconds] : tuned["provenance"]["seconds"].items()) {
    printRow("  " + part, seconds.get<double>(), sweep_seconds);
  }
  std::printf("  %zu estimator runs\n", tuned["provenance"]["estimator_runs"].get<std::size_t>());
}

}  // namespace

int main(int argc, char** argv) {
  const gtbake::bench::BenchArgs args = gtbake::bench::parseBenchArgs(argc, argv);
  fs::path sweep = args.path;
  const int threads = args.threads;
  const fs::path work =
      fs::temp_directory_path() / ("gtbake-bench-tune-" + std::to_string(getpid()));
  try {
    const auto start = std::chrono::steady_clock::now();
    if (sweep.empty()) sweep = sweepScenes(work / "sweep", threads);
    const double swept =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const nlohmann::ordered_json sweep_json = readJson(sweep / "sweep.json");
    const nlohmann::ordered_json::json_pointer at("/totals/seconds");
    const double sweep_seconds = sweep_json.contains(at) ? sweep_json[at].get<double>() : swept;
    std::printf("%d threads; sweep %s: %.2f s\n", threads, sweep.c_str(), sweep_seconds);
    std::printf("%-40s %9s %9s\n", "stage", "wall s", "/ sweep");
    gtbake::ScreenAoOptions s;
    s.sweep = sweep;
    s.out = work / "screen_ao";
    s.threads = threads;
    s.progress = false;
    printRow("screen-ao", gtbake::runScreenAo(s).seconds, sweep_seconds);
    benchTune(sweep, work, "alone (runs the defaults)", {}, threads, sweep_seconds);
    benchTune(sweep, work, "as in all (--screen-ao)", s.out, threads, sweep_seconds);
    fs::remove_all(work);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_tune: %s\n", e.what());
    fs::remove_all(work);
    return 1;
  }
  return 0;
}
