#include "pipeline/stage_clock.h"

#include <time.h>

#include <fstream>
#include <thread>

#include "common/output_set.h"
#include "common/text_format.h"
#include "gtbake_version.h"

namespace gtbake {

namespace {

double wallNow() {
  return clockSeconds(CLOCK_MONOTONIC);
}
double cpuNow() {
  return clockSeconds(CLOCK_PROCESS_CPUTIME_ID);
}

// The CPU's model name from /proc/cpuinfo ("" where there is none).
std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) != 0) continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) break;
    const std::size_t begin = line.find_first_not_of(' ', colon + 1);
    return begin == std::string::npos ? "" : line.substr(begin);
  }
  return "";
}

double cores(const StageTime& t) {
  return t.wall_seconds > 0.0 ? t.cpu_seconds / t.wall_seconds : 0.0;
}

}  // namespace

double clockSeconds(clockid_t id) {
  timespec t{};
  clock_gettime(id, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

StageClock::StageClock() : wall_start_(wallNow()), cpu_start_(cpuNow()) {}

void StageClock::run(const std::string& stage, const std::function<void()>& work) {
  const double wall = wallNow();
  const double cpu = cpuNow();
  const double background = background_cpu_ ? background_cpu_() : 0.0;
  work();
  const double background_used = background_cpu_ ? background_cpu_() - background : 0.0;
  stages_.push_back({stage, wallNow() - wall, cpuNow() - cpu - background_used});
}

void StageClock::addBackground(const std::vector<StageTime>& stages, double waited_seconds) {
  stages_.insert(stages_.end(), stages.begin(), stages.end());
  waited_seconds_ += waited_seconds;
}

StageTime StageClock::total() const {
  return {"total", wallNow() - wall_start_, cpuNow() - cpu_start_};
}

double StageClock::wallSeconds(const std::string& stage) const {
  for (const StageTime& t : stages_) {
    if (t.stage == stage) return t.wall_seconds;
  }
  return 0.0;
}

std::string stageTimeLine(const StageClock& clock) {
  std::string line;
  for (const StageTime& t : clock.stages()) {
    line += t.stage + " " + formatNumber(t.wall_seconds, "%.1f") + " s";
    line += t.background ? " in the background, " : ", ";
  }
  const StageTime total = clock.total();
  const double sweep = clock.wallSeconds("sweep");
  line.resize(line.size() - 2);
  if (clock.waitedSeconds() > 0.0) {
    line += "; waiting for the background " + formatNumber(clock.waitedSeconds(), "%.1f") + " s";
  }
  line += "; total " + formatNumber(total.wall_seconds, "%.1f") + " s";
  if (sweep > 0.0) line += " (" + formatNumber(total.wall_seconds / sweep, "%.1f") + "× the sweep)";
  return line + ", CPU " + formatNumber(cores(total), "%.2f") + " cores";
}

nlohmann::ordered_json timingsJson(const StageClock& clock, int threads) {
  const StageTime total = clock.total();
  const double sweep = clock.wallSeconds("sweep");
  nlohmann::ordered_json stages = nlohmann::ordered_json::array();
  for (const StageTime& t : clock.stages()) {
    stages.push_back(
        {{"stage", t.stage},
         {"wall_seconds", t.wall_seconds},
         {"cpu_seconds", t.cpu_seconds},
         {"cores_busy", cores(t)},
         {"background", t.background},
         {"share_of_total", total.wall_seconds > 0.0 ? t.wall_seconds / total.wall_seconds : 0.0}});
  }
  nlohmann::ordered_json timings;
  timings["machine"] = {{"cpu", cpuModel()},
                        {"logical_cores", std::thread::hardware_concurrency()}};
  timings["threads"] = threads;
  timings["stages"] = std::move(stages);
  timings["total"] = {{"wall_seconds", total.wall_seconds},
                      {"cpu_seconds", total.cpu_seconds},
                      {"cores_busy", cores(total)}};
  timings["waited_for_background_seconds"] = clock.waitedSeconds();
  timings["sweep_multiple"] = sweep > 0.0 ? total.wall_seconds / sweep : 0.0;
  timings["bar_seconds"] = kAllBarSeconds;
  timings["within_bar"] = total.wall_seconds <= kAllBarSeconds;
  nlohmann::ordered_json j;
  j["gtbake_version"] = GTBAKE_VERSION;
  j["timings"] = std::move(timings);
  return j;
}

void writeTimings(const std::filesystem::path& out, const StageClock& clock, int threads) {
  OutputSet set(out, "timings");
  set.add("timings.json", timingsJson(clock, threads).dump(2) + "\n");
  set.commit();
}

}  // namespace gtbake
