#include "pipeline/background_chain.h"

#include <pthread.h>

#include <algorithm>
#include <utility>

namespace gtbake {

BackgroundChain::WorkerClock::WorkerClock(tbb::task_arena& arena)
    : tbb::task_scheduler_observer(arena) {
  observe(true);
}

BackgroundChain::WorkerClock::~WorkerClock() {
  observe(false);  // waits for callbacks in progress
}

void BackgroundChain::WorkerClock::on_scheduler_entry(bool is_worker) {
  if (!is_worker) return;
  Visit v{pthread_self(), {}, 0.0};
  pthread_getcpuclockid(v.thread, &v.clock);
  v.entry_seconds = clockSeconds(v.clock);
  const std::lock_guard<std::mutex> lock(mutex_);
  open_.push_back(v);
}

void BackgroundChain::WorkerClock::on_scheduler_exit(bool is_worker) {
  if (!is_worker) return;
  const pthread_t self = pthread_self();
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto it = std::find_if(open_.begin(), open_.end(),
                               [&](const Visit& v) { return pthread_equal(v.thread, self); });
  if (it == open_.end()) return;
  closed_seconds_ += clockSeconds(it->clock) - it->entry_seconds;
  open_.erase(it);
}

double BackgroundChain::WorkerClock::seconds() const {
  // Under the lock a visit is open only while its worker is inside the arena, so its clock
  // names a live thread.
  const std::lock_guard<std::mutex> lock(mutex_);
  double total = closed_seconds_;
  for (const Visit& v : open_) total += clockSeconds(v.clock) - v.entry_seconds;
  return total;
}

BackgroundChain::BackgroundChain(int threads, std::function<void(BackgroundChain&)> work)
    : arena_(threads, 1, tbb::task_arena::priority::low),
      workers_(arena_),
      thread_([this, work = std::move(work)] { main(work); }) {}

BackgroundChain::~BackgroundChain() {
  cancel();
  if (thread_.joinable()) thread_.join();
}

void BackgroundChain::main(const std::function<void(BackgroundChain&)>& work) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    pthread_getcpuclockid(pthread_self(), &thread_clock_);
    started_ = true;
  }
  try {
    arena_.execute([&] { work(*this); });
  } catch (...) {
    const std::lock_guard<std::mutex> lock(mutex_);
    error_ = std::current_exception();
  }
  const std::lock_guard<std::mutex> lock(mutex_);
  finished_cpu_ = clockSeconds(CLOCK_THREAD_CPUTIME_ID);
  finished_ = true;  // from here on thread_clock_ may name a thread that has ended
}

void BackgroundChain::run(const std::string& stage, const std::function<void()>& fn) {
  if (cancelled_) return;
  const double wall = clockSeconds(CLOCK_MONOTONIC);
  const double cpu = cpuSeconds();
  fn();
  const StageTime t{stage, clockSeconds(CLOCK_MONOTONIC) - wall, cpuSeconds() - cpu, true};
  const std::lock_guard<std::mutex> lock(mutex_);
  stages_.push_back(t);
}

double BackgroundChain::cpuSeconds() const {
  double own = 0.0;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) {
      own = finished_cpu_;
    } else if (started_) {
      own = clockSeconds(thread_clock_);
    }
  }
  return own + workers_.seconds();
}

BackgroundChain::Joined BackgroundChain::join() {
  const double wall = clockSeconds(CLOCK_MONOTONIC);
  if (thread_.joinable()) thread_.join();
  Joined joined;
  joined.waited_seconds = clockSeconds(CLOCK_MONOTONIC) - wall;
  const std::lock_guard<std::mutex> lock(mutex_);
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  joined.stages = stages_;
  return joined;
}

}  // namespace gtbake
