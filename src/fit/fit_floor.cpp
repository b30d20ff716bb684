#include "fit/fit_floor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gtbake {

FitFloor fitFloor(const SweepData& data) {
  const std::size_t n = data.points();
  const std::size_t M = data.albedos.size();
  std::vector<int> bin(n);
  std::vector<std::size_t> count(kFloorBins, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = std::clamp(data.full.A[i], 0.0, 1.0);
    bin[i] = std::min(kFloorBins - 1, static_cast<int>(a * kFloorBins));
    ++count[bin[i]];
  }
  const auto occupied = static_cast<std::size_t>(
      std::count_if(count.begin(), count.end(), [](std::size_t c) { return c > 0; }));
  const double dof = static_cast<double>(n - occupied);
  FitFloor out;
  std::vector<double> scene_sum2(data.scenes.size(), 0.0);
  double total = 0.0;
  for (std::size_t j = 0; j < M; ++j) {
    std::vector<double> sum(kFloorBins, 0.0);
    for (std::size_t i = 0; i < n; ++i) sum[bin[i]] += data.full.G[j][i];
    for (int b = 0; b < kFloorBins; ++b) {
      if (count[b] > 0) sum[b] /= static_cast<double>(count[b]);
    }
    double albedo_sum2 = 0.0;
    for (std::size_t s = 0; s < data.scenes.size(); ++s) {
      for (std::size_t i = data.scenes[s].begin; i < data.scenes[s].end; ++i) {
        const double r = data.full.G[j][i] - sum[bin[i]];
        albedo_sum2 += r * r;
        scene_sum2[s] += r * r;
      }
    }
    total += albedo_sum2;
    char label[16];
    std::snprintf(label, sizeof(label), "%.2f", data.albedos[j]);
    out.per_albedo.push_back({label, data.albedos[j], std::sqrt(albedo_sum2 / dof)});
  }
  for (std::size_t s = 0; s < data.scenes.size(); ++s) {
    const double points = static_cast<double>(data.scenes[s].end - data.scenes[s].begin);
    const double share = static_cast<double>(n) / dof;  // the dof correction, shared pro rata
    out.per_scene.push_back(
        {data.scenes[s].name, 0.0, std::sqrt(scene_sum2[s] * share / (points * M))});
  }
  out.rmse = std::sqrt(total / (dof * static_cast<double>(M)));
  return out;
}

}  // namespace gtbake
