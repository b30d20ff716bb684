#include "common/threads.h"

#include <ImfThreading.h>
#include <tbb/info.h>

#include "common/error.h"

namespace gtbake {

ThreadLimit::ThreadLimit(int threads) {
  if (threads < 0) throw Error("--threads must be 0 (all cores) or a positive count");
  threads_ = threads == 0 ? tbb::info::default_concurrency() : threads;
  control_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                   static_cast<size_t>(threads_));
  // Only a change touches OpenEXR's pool, so that a limit the same as the one in force (a stage
  // of `gtbake all`, some running on a thread of their own: background_chain.h) never resizes
  // the pool under another thread's image.
  exr_threads_before_ = Imf::globalThreadCount();
  const int exr_threads = threads_ > 1 ? threads_ : 0;
  if (exr_threads != exr_threads_before_) Imf::setGlobalThreadCount(exr_threads);
}

ThreadLimit::~ThreadLimit() {
  if (Imf::globalThreadCount() != exr_threads_before_) {
    Imf::setGlobalThreadCount(exr_threads_before_);
  }
}

}  // namespace gtbake
