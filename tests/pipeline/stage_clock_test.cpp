// The stage times of `gtbake all` (docs/performance.md "Stage times"): wall and CPU seconds told
// apart, in run order, and written as an output set.
#include "pipeline/stage_clock.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "common/output_set.h"
#include "support/temp_dir.h"

namespace gtbake {
namespace {

using namespace std::chrono_literals;

// Burns about `seconds` of this thread's CPU time.
void spin(double seconds) {
  timespec t{};
  const auto now = [&] {
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  };
  const double start = now();
  volatile double sink = 0.0;
  while (now() - start < seconds) sink = sink + 1.0;
}

TEST(StageClock, TellsWaitingFromWorking) {
  StageClock clock;
  clock.run("sweep", [] { std::this_thread::sleep_for(150ms); });
  clock.run("fit", [] { spin(0.15); });
  ASSERT_EQ(clock.stages().size(), 2u);
  const StageTime& waited = clock.stages()[0];
  const StageTime& worked = clock.stages()[1];
  EXPECT_EQ(waited.stage, "sweep");
  EXPECT_GE(waited.wall_seconds, 0.15);
  EXPECT_LT(waited.cpu_seconds, 0.05);  // sleeping costs no CPU
  EXPECT_EQ(worked.stage, "fit");
  EXPECT_GE(worked.cpu_seconds, 0.14);
  EXPECT_GE(worked.wall_seconds, 0.9 * worked.cpu_seconds);  // one thread: no more CPU than wall
  const StageTime total = clock.total();
  EXPECT_GE(total.wall_seconds, waited.wall_seconds + worked.wall_seconds);
  EXPECT_EQ(clock.wallSeconds("sweep"), waited.wall_seconds);
  EXPECT_EQ(clock.wallSeconds("tune"), 0.0);
}

TEST(StageClock, JsonHoldsEveryStageAndTheMultipleOfTheSweep) {
  StageClock clock;
  clock.run("sweep", [] { std::this_thread::sleep_for(100ms); });
  clock.run("tune", [] { std::this_thread::sleep_for(100ms); });
  const nlohmann::ordered_json j = timingsJson(clock, 2);
  const auto& t = j.at("timings");
  ASSERT_EQ(t.at("stages").size(), 2u);
  EXPECT_EQ(t["stages"][0]["stage"], "sweep");
  EXPECT_EQ(t["stages"][1]["stage"], "tune");
  EXPECT_EQ(t["threads"], 2);
  const double sweep = t["stages"][0]["wall_seconds"].get<double>();
  const double total = t["total"]["wall_seconds"].get<double>();
  EXPECT_NEAR(t["sweep_multiple"].get<double>(), total / sweep, 1e-12);
  EXPECT_GT(t["sweep_multiple"].get<double>(), 1.9);  // the sweep is half of it
  EXPECT_LT(t["sweep_multiple"].get<double>(), 2.5);
  EXPECT_EQ(t["within_bar"], total <= kAllBarSeconds);
  const std::string line = stageTimeLine(clock);
  EXPECT_EQ(line.rfind("sweep 0.1 s, tune 0.1 s; total 0.2 s (2.", 0), 0u) << line;
}

TEST(StageClock, WritesTimingsAsAnOutputSet) {
  const test::TempDir dir("stage_clock");
  StageClock clock;
  clock.run("sweep", [] {});
  writeTimings(dir.path(), clock, 1);
  const OutputManifest m = readOutputSet(dir.path(), "timings");
  const auto doc = nlohmann::json::parse(m.readVerified("timings.json"));
  EXPECT_EQ(doc["timings"]["stages"][0]["stage"], "sweep");
}

}  // namespace
}  // namespace gtbake
