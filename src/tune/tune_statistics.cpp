#include "tune/tune_statistics.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "common/error.h"

namespace gtbake {

ClusterStatistics& ClusterStatistics::operator+=(const ClusterStatistics& other) {
  sums += other.sums;
  if (q.size() < other.q.size()) q.resize(other.q.size(), 0.0L);
  for (std::size_t j = 0; j < other.q.size(); ++j) q[j] += other.q[j];
  return *this;
}

std::vector<std::vector<long double>> clusterTargetSquares(const SweepData& data,
                                                           const Grouping& clusters) {
  const std::size_t M = data.albedos.size();
  std::vector<std::vector<long double>> q(clusters.names.size(), std::vector<long double>(M, 0.0L));
  for (std::size_t v = 0; v < data.scenes.size(); ++v) {
    for (std::size_t j = 0; j < M; ++j) {
      // Blocks of kSumBlock points in double, accumulated in long double (normal_equations.h).
      const SweepScene& s = data.scenes[v];
      for (std::size_t begin = s.begin; begin < s.end; begin += kSumBlock) {
        double part = 0.0;
        for (std::size_t i = begin; i < std::min(s.end, begin + kSumBlock); ++i) {
          part += data.full.G[j][i] * data.full.G[j][i];
        }
        q[clusters.of[v]][j] += part;
      }
    }
  }
  return q;
}

std::vector<ClusterStatistics> clusterStatistics(
    const SweepData& data, const Grouping& clusters,
    const std::vector<std::vector<long double>>& target_squares) {
  const std::size_t M = data.albedos.size();
  std::vector<ClusterStatistics> out(clusters.names.size());
  tbb::parallel_for(std::size_t{0}, out.size(), [&](std::size_t c) {
    out[c].sums.moment.assign(M, {});
    out[c].q = target_squares[c];
    for (std::size_t v = 0; v < data.scenes.size(); ++v) {
      if (clusters.of[v] != c) continue;
      const SweepScene& s = data.scenes[v];
      const std::vector<double> w(s.end - s.begin, 1.0);
      std::vector<const double*> g(M);
      for (std::size_t j = 0; j < M; ++j) g[j] = data.full.G[j].data() + s.begin;
      accumulate(out[c].sums, w.data(), data.full.A.data() + s.begin, g, s.end - s.begin);
    }
  });
  return out;
}

ClusterStatistics sumClusters(const std::vector<ClusterStatistics>& clusters,
                              const std::vector<bool>& include) {
  ClusterStatistics total;
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    if (include.empty() || include[c]) total += clusters[c];
  }
  return total;
}

double sumSquaredError(const ClusterStatistics& s, const std::vector<double>& albedos,
                       const MultiBounceCoeffs& k) {
  long double sse = 0.0L;
  for (std::size_t j = 0; j < albedos.size(); ++j) {
    const Cubic theta = cubicAt(k, albedos[j]);
    long double quadratic = 0.0L, linear = 0.0L;
    for (int r = 0; r < 3; ++r) {
      linear += theta[r] * s.sums.moment[j][r];
      for (int c = 0; c < 3; ++c) quadratic += theta[r] * s.sums.gram[3 * r + c] * theta[c];
    }
    sse += s.q[j] - 2.0L * linear + quadratic;
  }
  return static_cast<double>(std::max(sse, 0.0L));
}

MultiBounceCoeffs refitCoefficients(const ClusterStatistics& s, const std::vector<double>& albedos,
                                    const FitSettings& settings) {
  if (settings.eiv_correction) {
    throw Error("internal: a tune refit has no noise levels (errors-in-variables is off)");
  }
  // Without the correction only level 0 is read; the others repeat it so every solve is defined.
  LevelStatistics levels;
  levels.fill(s.sums);
  return coefficientsFromStatistics(levels, albedos, settings);
}

double directSquaredError(const SweepData& data, const std::vector<std::size_t>& views,
                          const MultiBounceCoeffs& k) {
  double sse = 0.0;
  for (std::size_t j = 0; j < data.albedos.size(); ++j) {
    const Cubic theta = cubicAt(k, data.albedos[j]);
    for (std::size_t v : views) {
      for (std::size_t i = data.scenes[v].begin; i < data.scenes[v].end; ++i) {
        const double e = data.full.G[j][i] - evalCubic(theta, data.full.A[i]);
        sse += e * e;
      }
    }
  }
  return sse;
}

}  // namespace gtbake
