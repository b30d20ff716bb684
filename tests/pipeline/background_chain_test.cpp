// The chain of stages `gtbake all` runs beside the foreground (docs/performance.md "Stages in the
// background"): its CPU seconds counted apart from the foreground's, its stages recorded in
// order, its errors rethrown at join, and a cancel that skips what has not started.
#include "pipeline/background_chain.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "common/threads.h"

namespace gtbake {
namespace {

using namespace std::chrono_literals;

double threadCpu() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Burns about `seconds` of the calling thread's CPU time.
void spin(double seconds) {
  const double start = threadCpu();
  volatile double sink = 0.0;
  while (threadCpu() - start < seconds) sink = sink + 1.0;
}

TEST(BackgroundChain, RunsItsStagesInOrderOnAThreadOfItsOwn) {
  std::thread::id ran_on;
  BackgroundChain chain(2, [&](BackgroundChain& c) {
    c.run("gtso", [&] {
      ran_on = std::this_thread::get_id();
      spin(0.1);
    });
    c.run("encode", [] { std::this_thread::sleep_for(100ms); });
  });
  const BackgroundChain::Joined joined = chain.join();
  EXPECT_NE(ran_on, std::this_thread::get_id());
  ASSERT_EQ(joined.stages.size(), 2u);
  EXPECT_EQ(joined.stages[0].stage, "gtso");
  EXPECT_EQ(joined.stages[1].stage, "encode");
  EXPECT_TRUE(joined.stages[0].background);
  EXPECT_GE(joined.stages[0].cpu_seconds, 0.095);
  EXPECT_LT(joined.stages[1].cpu_seconds, 0.05);  // sleeping costs no CPU
  EXPECT_GE(joined.stages[1].wall_seconds, 0.1);
  EXPECT_GT(joined.waited_seconds, 0.0);
}

// The chain's TBB loops run in its own arena; the CPU a worker spends there is the chain's.
TEST(BackgroundChain, CountsTheWorkersOfItsLoops) {
  const ThreadLimit limit(2);
  std::atomic<int> on_other_threads{0};
  BackgroundChain chain(2, [&](BackgroundChain& c) {
    c.run("gtso", [&] {
      const std::thread::id own = std::this_thread::get_id();
      tbb::parallel_for(0, 8, 1, [&](int) {
        if (std::this_thread::get_id() != own) ++on_other_threads;
        spin(0.05);
      });
    });
  });
  const BackgroundChain::Joined joined = chain.join();
  ASSERT_EQ(joined.stages.size(), 1u);
  // 8 × 0.05 s of spinning, whichever threads ran it, and nothing else of note.
  EXPECT_GE(joined.stages[0].cpu_seconds, 0.39);
  EXPECT_LT(joined.stages[0].cpu_seconds, 0.6);
  EXPECT_GE(chain.cpuSeconds(), joined.stages[0].cpu_seconds);
  if (on_other_threads == 0)
    GTEST_SKIP() << "no worker joined the arena; the sum above still holds";
}

TEST(BackgroundChain, RethrowsAStageErrorAtJoinAndRunsNothingAfterIt) {
  bool after = false;
  BackgroundChain chain(1, [&](BackgroundChain& c) {
    c.run("gtso", [] { throw std::runtime_error("gtso: no memory"); });
    c.run("encode", [&] { after = true; });
  });
  EXPECT_THROW(
      {
        try {
          chain.join();
        } catch (const std::runtime_error& e) {
          EXPECT_STREQ(e.what(), "gtso: no memory");
          throw;
        }
      },
      std::runtime_error);
  EXPECT_FALSE(after);
}

TEST(BackgroundChain, CancelSkipsTheStagesNotYetStarted) {
  std::atomic<bool> running{false};
  std::atomic<bool> release{false};
  std::atomic<bool> second{false};
  {
    BackgroundChain chain(1, [&](BackgroundChain& c) {
      c.run("gtso", [&] {
        running = true;
        while (!release) std::this_thread::sleep_for(1ms);
      });
      c.run("encode", [&] { second = true; });
    });
    while (!running) std::this_thread::sleep_for(1ms);
    chain.cancel();
    release = true;
    const BackgroundChain::Joined joined = chain.join();
    ASSERT_EQ(joined.stages.size(), 1u);
    EXPECT_EQ(joined.stages[0].stage, "gtso");
  }
  EXPECT_FALSE(second);
}

// A foreground stage's CPU leaves out what the chain used meanwhile; the total keeps both.
TEST(BackgroundChain, ForegroundStagesDoNotCountTheChain) {
  StageClock clock;
  std::atomic<bool> go{false};
  BackgroundChain chain(1, [&](BackgroundChain& c) {
    c.run("gtso", [&] {
      while (!go) std::this_thread::sleep_for(1ms);
      spin(0.3);
    });
  });
  clock.setBackgroundCpu([&] { return chain.cpuSeconds(); });
  clock.run("screen-ao", [&] {
    go = true;
    std::this_thread::sleep_for(500ms);  // the chain spins meanwhile
  });
  const BackgroundChain::Joined joined = chain.join();
  clock.setBackgroundCpu(nullptr);
  clock.addBackground(joined.stages, joined.waited_seconds);
  ASSERT_EQ(clock.stages().size(), 2u);
  EXPECT_LT(clock.stages()[0].cpu_seconds, 0.05) << "the sleeping foreground used next to none";
  EXPECT_GE(clock.stages()[1].cpu_seconds, 0.29);
  EXPECT_TRUE(clock.stages()[1].background);
  EXPECT_GE(clock.total().cpu_seconds, 0.29);
  const std::string line = stageTimeLine(clock);
  EXPECT_EQ(line.rfind("screen-ao 0.5 s, gtso ", 0), 0u) << line;
  EXPECT_NE(line.find(" s in the background; "), std::string::npos) << line;
  const nlohmann::ordered_json j = timingsJson(clock, 2);
  EXPECT_EQ(j["timings"]["stages"][1]["background"], true);
  EXPECT_EQ(j["timings"]["stages"][0]["background"], false);
  EXPECT_EQ(j["timings"]["waited_for_background_seconds"].get<double>(), joined.waited_seconds);
}

}  // namespace
}  // namespace gtbake
