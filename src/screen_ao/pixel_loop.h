// The loop every estimator and filter runs: f(i, j, p) for each pixel that sees geometry, rows
// split across TBB workers (each pixel's outputs are written by its own call only).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstddef>

#include "screen_ao/gbuffer.h"

namespace gtbake {

template <typename F>
void forEachMaskedPixel(const GBuffer& g, F f) {
  tbb::parallel_for(tbb::blocked_range<int>(0, g.height), [&](const tbb::blocked_range<int>& r) {
    for (int j = r.begin(); j != r.end(); ++j) {
      for (int i = 0; i < g.width; ++i) {
        const std::size_t p = static_cast<std::size_t>(j) * g.width + i;
        if (g.mask[p] != 0) f(i, j, p);
      }
    }
  });
}

}  // namespace gtbake
