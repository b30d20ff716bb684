#include "common/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace gtbake {

namespace {
constexpr int kBarWidth = 30;                                     // characters in the drawn bar
constexpr auto kRedrawInterval = std::chrono::milliseconds(100);  // terminal refresh rate
}  // namespace

Progress::Progress(std::string label, std::uint64_t total, bool enabled)
    : label_(std::move(label)),
      total_(std::max<std::uint64_t>(total, 1)),
      enabled_(enabled),
      tty_(::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() {
  finish();
}

void Progress::add(std::uint64_t units) {
  const std::uint64_t done = done_.fetch_add(units, std::memory_order_relaxed) + units;
  if (!enabled_) return;
  std::unique_lock<std::mutex> lock(draw_mutex_, std::try_to_lock);
  if (lock.owns_lock()) draw(done, false);
}

void Progress::finish() {
  if (finished_.exchange(true)) return;
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(draw_mutex_);
  draw(total_, true);
}

void Progress::draw(std::uint64_t done, bool final) {
  const auto now = std::chrono::steady_clock::now();
  const double fraction = std::min(1.0, static_cast<double>(done) / static_cast<double>(total_));
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (!final) {
    if (tty_) {
      if (now - last_draw_ < kRedrawInterval) return;
    } else {
      const int decile = static_cast<int>(fraction * 10.0);
      if (decile <= last_decile_ || decile >= 10) return;
      last_decile_ = decile;
    }
  }
  last_draw_ = now;
  const int filled = static_cast<int>(fraction * kBarWidth);
  std::string bar(static_cast<size_t>(filled), '#');
  bar.append(static_cast<size_t>(kBarWidth - filled), '.');
  char tail[64];
  if (final) {
    std::snprintf(tail, sizeof tail, "done in %.1f s", elapsed);
  } else if (fraction > 0.0) {
    std::snprintf(tail, sizeof tail, "ETA %.0f s", elapsed * (1.0 - fraction) / fraction);
  } else {
    std::snprintf(tail, sizeof tail, "ETA --");
  }
  std::fprintf(stderr, "%s%-10s [%s] %3.0f%%  %s%s", tty_ ? "\r" : "", label_.c_str(), bar.c_str(),
               fraction * 100.0, tail, (tty_ && !final) ? "\033[K" : "\n");
  std::fflush(stderr);
}

}  // namespace gtbake
