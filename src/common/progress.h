// Progress bar with an ETA on stderr, safe to advance from many threads.
//
// On a terminal it redraws one line ("label [#####.....]  45%  ETA 12 s"); when stderr is not a
// terminal (CI, a pipe) it prints a plain line at most every 10% so logs stay short. Quiet mode
// (tests, nested stages) prints nothing. Progress never touches stdout, which carries results.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace gtbake {

class Progress {
 public:
  Progress(std::string label, std::uint64_t total, bool enabled = true);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void add(std::uint64_t units);
  // Draws the final state (100% and the elapsed time); called by the destructor if not before.
  void finish();
  // Ends the bar where it stands, without drawing (the work was interrupted, not finished).
  void abandon();

 private:
  void draw(std::uint64_t done, bool final);

  std::string label_;
  std::uint64_t total_;
  bool enabled_;
  bool tty_;
  std::atomic<std::uint64_t> done_{0};
  std::atomic<bool> finished_{false};
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  int last_decile_ = -1;
  std::mutex draw_mutex_;
};

// The named parts of one stage, each run under its own bar labelled "<stage>: <part>" and timed,
// so a long stage says where it is and reports where its time went.
class StageParts {
 public:
  StageParts(std::string stage, bool enabled) : stage_(std::move(stage)), enabled_(enabled) {}

  // Runs f(Progress&) under a bar of `total` units and records the part's wall seconds.
  template <typename F>
  auto run(const std::string& part, std::uint64_t total, F&& f) {
    const auto start = std::chrono::steady_clock::now();
    Progress bar(stage_ + ": " + part, total, enabled_);
    auto result = f(bar);
    bar.finish();
    seconds_.emplace_back(
        part, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return result;
  }
  // (part, seconds) in the order run.
  const std::vector<std::pair<std::string, double>>& seconds() const { return seconds_; }

 private:
  std::string stage_;
  bool enabled_;
  std::vector<std::pair<std::string, double>> seconds_;
};

}  // namespace gtbake
