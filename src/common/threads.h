// Thread-count control shared by every stage: TBB runs every parallel loop in gtbake, and
// OpenEXR's own pool compresses and decompresses an image's line blocks.
#pragma once

#include <tbb/global_control.h>

#include <memory>

namespace gtbake {

// While alive, limits TBB to `threads` workers (0 = all hardware threads) and gives OpenEXR as
// many threads for an image's line blocks (none with one: the caller's thread does them). Results
// never depend on the count: every parallel loop writes disjoint outputs and reduces in a fixed
// order, and OpenEXR writes and reads the blocks in file order whichever thread (de)compressed
// them.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();  // OpenEXR's pool back to what it was
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;
  int threads() const { return threads_; }

 private:
  int threads_;
  int exr_threads_before_;
  std::unique_ptr<tbb::global_control> control_;
};

}  // namespace gtbake
