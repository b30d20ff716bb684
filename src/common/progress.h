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

}  // namespace gtbake
