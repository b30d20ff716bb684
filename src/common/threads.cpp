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
  exr_threads_before_ = Imf::globalThreadCount();
  Imf::setGlobalThreadCount(threads_ > 1 ? threads_ : 0);
}

ThreadLimit::~ThreadLimit() {
  Imf::setGlobalThreadCount(exr_threads_before_);
}

}  // namespace gtbake
