// The wall and CPU seconds of each stage of `gtbake all`, printed in its summary and written as
// <out>/timings.json (docs/performance.md "Stage times"): what a machine spends where, and how
// much of its cores each stage keeps busy.
#pragma once

#include <time.h>

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace gtbake {

// The bar for `gtbake all` at its defaults on 2 cores (docs/performance.md).
inline constexpr double kAllBarSeconds = 150.0;

// The reading of a POSIX clock in seconds (CLOCK_MONOTONIC, a process's or a thread's CPU clock).
double clockSeconds(clockid_t id);

struct StageTime {
  std::string stage;
  double wall_seconds = 0.0;
  // The process's user and system time over the stage, every thread, less what a chain in the
  // background used meanwhile (background_chain.h); a background stage's own threads' time.
  double cpu_seconds = 0.0;
  bool background = false;  // ran beside the foreground stages (background_chain.h)
};

class StageClock {
 public:
  StageClock();  // the total starts here
  // Runs `work` and records its wall and CPU seconds under `stage`.
  void run(const std::string& stage, const std::function<void()>& work);
  // While set, each foreground stage's CPU seconds leave out what `cpu` (a running total of the
  // chain in the background) grew by meanwhile.
  void setBackgroundCpu(std::function<double()> cpu) { background_cpu_ = std::move(cpu); }
  // Appends the stages a background chain ran, and the wall seconds the foreground waited for it.
  void addBackground(const std::vector<StageTime>& stages, double waited_seconds);
  const std::vector<StageTime>& stages() const { return stages_; }
  double waitedSeconds() const { return waited_seconds_; }
  StageTime total() const;
  // The wall seconds of `stage` (0 when it did not run).
  double wallSeconds(const std::string& stage) const;

 private:
  std::vector<StageTime> stages_;
  double wall_start_ = 0.0;
  double cpu_start_ = 0.0;
  std::function<double()> background_cpu_;
  double waited_seconds_ = 0.0;
};

// "scenes 1.0 s, sweep 30.7 s, ..., gtso 13.1 s in the background, ...; waiting for the background
// 2.0 s; total 227.0 s (7.4× the sweep), CPU 1.78 cores".
std::string stageTimeLine(const StageClock& clock);

// The timings as JSON: every value under "timings", which measures the run (docs/performance.md
// "Stage times" lists the fields).
nlohmann::ordered_json timingsJson(const StageClock& clock, int threads);

// Writes timingsJson as <out>/timings.json, an output set of its own (timings.manifest.json).
void writeTimings(const std::filesystem::path& out, const StageClock& clock, int threads);

}  // namespace gtbake
