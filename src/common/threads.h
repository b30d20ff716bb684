// Thread-count control shared by every stage: TBB runs every parallel loop in gtbake.
#pragma once

#include <tbb/global_control.h>

#include <memory>

namespace gtbake {

// While alive, limits TBB to `threads` workers (0 = all hardware threads). Results never depend
// on the count: every parallel loop writes disjoint outputs and reduces in a fixed order.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  int threads() const { return threads_; }

 private:
  int threads_;
  std::unique_ptr<tbb::global_control> control_;
};

}  // namespace gtbake
