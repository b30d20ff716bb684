// A chain of stages of `gtbake all` run on a thread of its own beside the stages in the
// foreground, so that it uses the cores the foreground leaves idle (docs/performance.md "Stages
// in the background"). Its outputs are the same bytes as when the stages run in turn: nothing it
// runs reads what the foreground writes, or the reverse, until join() returns.
#pragma once

#include <pthread.h>
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>
#include <time.h>

#include <atomic>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "pipeline/stage_clock.h"

namespace gtbake {

class BackgroundChain {
 public:
  // Starts `work` at once on a new thread, its TBB loops in a low-priority arena of `threads`
  // slots (TBB's workers serve the foreground's loops first); `work` runs its stages through
  // run().
  BackgroundChain(int threads, std::function<void(BackgroundChain&)> work);
  ~BackgroundChain();  // cancel() and waits: no stage outlives the chain
  BackgroundChain(const BackgroundChain&) = delete;
  BackgroundChain& operator=(const BackgroundChain&) = delete;

  // Runs one stage of the chain (from `work` only) and records its wall and CPU seconds; skipped
  // once the chain is cancelled.
  void run(const std::string& stage, const std::function<void()>& fn);
  // Stages not yet started are skipped (the one running finishes: stages have no stop points).
  void cancel() { cancelled_ = true; }
  // The CPU seconds the chain has used so far: its own thread, and TBB's workers while they were
  // in its arena (WorkerClock).
  double cpuSeconds() const;

  struct Joined {
    std::vector<StageTime> stages;  // in the order they ran, each marked background
    double waited_seconds = 0.0;    // wall seconds join() blocked the caller
  };
  // Waits for the chain; rethrows the first exception of a stage.
  Joined join();

 private:
  // The CPU time TBB's workers spend in the chain's arena: closed visits summed, open ones read
  // off each worker's CPU clock, so a worker still in the arena counts up to now.
  class WorkerClock : public tbb::task_scheduler_observer {
   public:
    explicit WorkerClock(tbb::task_arena& arena);
    ~WorkerClock() override;
    void on_scheduler_entry(bool is_worker) override;
    void on_scheduler_exit(bool is_worker) override;
    double seconds() const;

   private:
    struct Visit {
      pthread_t thread;
      clockid_t clock;
      double entry_seconds;
    };
    mutable std::mutex mutex_;
    double closed_seconds_ = 0.0;
    std::vector<Visit> open_;
  };

  void main(const std::function<void(BackgroundChain&)>& work);

  tbb::task_arena arena_;
  WorkerClock workers_;
  std::atomic<bool> cancelled_{false};
  mutable std::mutex mutex_;   // guards the fields below
  bool started_ = false;       // thread_clock_ is set
  clockid_t thread_clock_{};   // the chain thread's CPU clock while it runs
  bool finished_ = false;      // the thread has read its final CPU time
  double finished_cpu_ = 0.0;  // ... which is this
  std::vector<StageTime> stages_;
  std::exception_ptr error_;
  std::thread thread_;  // last: starts once every field above exists
};

}  // namespace gtbake
