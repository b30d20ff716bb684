// bench_all: `gtbake all` stage by stage, in one run, against its own sweep and against a baseline
// run (docs/performance.md "Stage times"). Runs `gtbake all` with its defaults into OUT (default:
// a fresh temporary directory, removed afterwards), then prints each stage's wall and CPU seconds,
// the cores it kept busy, its multiple of the sweep's wall time, and the ratio of its wall time
// to the same stage's in the baseline's timings.json (default: luts/timings.json, the run that
// wrote luts/).
//
//   bench_all [OUT] [--baseline TIMINGS_JSON] [--threads T]
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "pipeline/all_command.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json readTimings(const fs::path& file) {
  std::ifstream in(file);
  if (!in) {
    std::fprintf(stderr, "bench_all: cannot read %s\n", file.c_str());
    std::exit(1);
  }
  return json::parse(in).at("timings");
}

double sweepWall(const json& t) {
  for (const json& s : t.at("stages")) {
    if (s.at("stage") == "sweep") return s.at("wall_seconds").get<double>();
  }
  return 0.0;
}

void printTable(const json& run, const json& baseline) {
  std::map<std::string, double> before;
  for (const json& s : baseline.at("stages")) {
    before[s.at("stage").get<std::string>()] = s.at("wall_seconds").get<double>();
  }
  const double sweep = sweepWall(run);
  std::printf("%-28s %9s %9s %6s %9s %10s %7s\n", "stage", "wall s", "CPU s", "cores", "× sweep",
              "baseline s", "ratio");
  const auto row = [&](const std::string& name, const json& s, double base) {
    const double wall = s.at("wall_seconds").get<double>();
    std::printf("%-28s %9.1f %9.1f %6.2f %9.2f %10.1f %7.2f\n", name.c_str(), wall,
                s.at("cpu_seconds").get<double>(), s.at("cores_busy").get<double>(),
                sweep > 0.0 ? wall / sweep : 0.0, base, base > 0.0 ? wall / base : 0.0);
  };
  for (const json& s : run.at("stages")) {
    const std::string name = s.at("stage");
    const bool background = s.value("background", false);  // beside the others: wall overlaps
    row(background ? name + " (background)" : name, s,
        before.count(name) != 0 ? before[name] : 0.0);
  }
  if (run.contains("waited_for_background_seconds")) {
    std::printf("%-28s %9.1f\n", "waiting for the background",
                run.at("waited_for_background_seconds").get<double>());
  }
  row("total", run.at("total"), baseline.at("total").at("wall_seconds").get<double>());
  std::printf("machine: %s, %d threads; bar %.0f s: %s\n",
              run.at("machine").at("cpu").get<std::string>().c_str(), run.at("threads").get<int>(),
              run.at("bar_seconds").get<double>(),
              run.at("within_bar").get<bool>() ? "met" : "not met");
}

}  // namespace

int main(int argc, char** argv) {
  fs::path out;
  fs::path baseline = fs::path(GTBAKE_SOURCE_DIR) / "luts" / "timings.json";
  int threads = 2;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--baseline" && i + 1 < argc) {
      baseline = argv[++i];
    } else if (arg == "--threads" && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else {
      out = arg;
    }
  }
  const json before = readTimings(baseline);  // before the long run: a bad path fails at once
  const bool temporary = out.empty();
  if (temporary) out = fs::temp_directory_path() / ("bench_all_" + std::to_string(::getpid()));
  gtbake::AllOptions options;
  options.out = out;
  options.threads = threads;
  options.command_line = "bench_all";
  gtbake::runAll(options);
  printTable(readTimings(out / "timings.json"), before);
  if (temporary) fs::remove_all(out);
  return 0;
}
