// Runs countEscapes at many points (in parallel, reduced in a fixed order) for closed-form tests.
#pragma once

#include <tbb/parallel_for.h>

#include <vector>

#include "sweep/escape_walk.h"

namespace gtbake::test {

struct PointEstimate {
  std::vector<double> p;  // p̂_k pooled over all points and walks, k = 0..K
  double walks = 0.0;     // points × spp

  // Ĝ(ρ) = Σ ρ^k p̂_k.
  double g(double rho) const {
    double sum = 0.0;
    for (std::size_t k = p.size(); k-- > 0;) sum = sum * rho + p[k];
    return sum;
  }
};

inline PointEstimate walkPoints(const EmbreeTracer& tracer, const std::vector<SurfaceHit>& points,
                                const WalkSettings& settings) {
  const std::size_t per_point = 2 * static_cast<std::size_t>(settings.bounces + 1);
  std::vector<std::uint32_t> counts(points.size() * per_point, 0);
  tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) {
    WalkScratch scratch;
    countEscapes(tracer, points[i], settings, i, &counts[i * per_point], &scratch);
  });
  PointEstimate e;
  e.p.assign(settings.bounces + 1, 0.0);
  e.walks = static_cast<double>(points.size()) * settings.spp;
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int h = 0; h < 2; ++h) {
      for (int k = 0; k <= settings.bounces; ++k) {
        e.p[k] += counts[i * per_point + h * (settings.bounces + 1) + k];
      }
    }
  }
  for (double& v : e.p) v /= e.walks;
  return e;
}

}  // namespace gtbake::test
