#include "tune/tune_optimum.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"
#include "stats/jackknife.h"

namespace gtbake {

double curveArgmin(const std::vector<double>& x, const std::vector<double>& y, bool* at_bound) {
  const auto k = static_cast<std::size_t>(std::min_element(y.begin(), y.end()) - y.begin());
  *at_bound = k == 0 || k + 1 == y.size();
  if (*at_bound) return x[k];
  // Newton's form on x_{k+1}, x_k, x_{k−1}: p(t) = y_{k+1} + d_right (t − x_{k+1})
  // + curvature (t − x_{k+1})(t − x_k). y_k is the smallest, so the vertex lies in the bracket.
  const double h0 = x[k] - x[k - 1], h1 = x[k + 1] - x[k];
  const double d_left = (y[k] - y[k - 1]) / h0, d_right = (y[k + 1] - y[k]) / h1;
  const double curvature = (d_right - d_left) / (h0 + h1);
  if (!(curvature > 0.0)) return x[k];
  // p'(t) = d_right + curvature (2t − x_k − x_{k+1}) = 0.
  return 0.5 * (x[k] + x[k + 1]) - 0.5 * d_right / curvature;
}

SceneInterval sceneInterval(const std::vector<double>& x, const std::vector<double>& pooled,
                            const std::vector<std::vector<double>>& replicas) {
  const std::size_t S = replicas.size();
  if (S < kMinJackknifeScenes) {
    throw Error("tune: the scene-level interval needs at least " +
                std::to_string(kMinJackknifeScenes) + " scenes, the sweep has " +
                std::to_string(S));
  }
  SceneInterval out;
  out.z = curveArgmin(x, pooled, &out.at_bound);
  for (const std::vector<double>& curve : replicas) {
    bool bound = false;
    out.replicates.push_back(curveArgmin(x, curve, &bound));
    out.replicates_at_bound += bound ? 1 : 0;
  }
  out.se = jackknifeSe(out.replicates);
  out.t = studentT975(S - 1);
  // The interval says nothing beyond what was searched (docs/tune.md §3): clipped to the grid.
  const double low = out.z - out.t * out.se, high = out.z + out.t * out.se;
  out.interval_clipped = low < x.front() || high > x.back();
  out.low = std::max(low, x.front());
  out.high = std::min(high, x.back());
  const auto k =
      static_cast<std::size_t>(std::min_element(pooled.begin(), pooled.end()) - pooled.begin());
  const double limit = (1.0 + kFlatFraction) * pooled[k];
  std::size_t lo = k, hi = k;
  while (lo > 0 && pooled[lo - 1] <= limit) --lo;
  while (hi + 1 < pooled.size() && pooled[hi + 1] <= limit) ++hi;
  out.flat_first = lo;
  out.flat_last = hi;
  return out;
}

}  // namespace gtbake
