#include "validate_gtso/so_floor.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>

#include "common/error.h"

namespace gtbake {

namespace {

constexpr int kInputs = 4;  // A, b·n, b·ωr, n·ωr (r_p is fixed per roughness)

std::array<double, kInputs> inputs(const SpecularSample& s) {
  return {s.A, s.n_dot_b, s.cos_beta, s.n_dot_v};
}

using Bins = std::array<std::vector<int>, kInputs>;  // [input][k]: each sample's bin

// Equal-count bins of every sample for each input, for each bin count in `counts`: one sort per
// input serves every count.
std::vector<Bins> binsOf(const std::vector<SpecularSample>& samples,
                         const std::vector<std::size_t>& index, const std::vector<int>& counts) {
  std::vector<Bins> out(counts.size());
  tbb::parallel_for(0, kInputs, [&](int f) {
    std::vector<double> v;
    for (std::size_t i : index) v.push_back(inputs(samples[i])[f]);
    std::vector<double> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t c = 0; c < counts.size(); ++c) {
      std::vector<double> edges;
      for (int b = 1; b < counts[c]; ++b) edges.push_back(sorted[sorted.size() * b / counts[c]]);
      for (double x : v) {
        out[c][f].push_back(
            static_cast<int>(std::upper_bound(edges.begin(), edges.end(), x) - edges.begin()));
      }
    }
  });
  return out;
}

// Sums and counts of the truth per (cluster, cell), and their totals over clusters.
struct CellMeans {
  std::vector<std::vector<double>> sum;  // [cluster][cell]
  std::vector<std::vector<double>> n;
  std::vector<double> total_sum, total_n;
  CellMeans(std::size_t clusters, std::size_t cells)
      : sum(clusters, std::vector<double>(cells, 0.0)),
        n(clusters, std::vector<double>(cells, 0.0)),
        total_sum(cells, 0.0),
        total_n(cells, 0.0) {}
  void add(std::size_t c, std::size_t cell, double truth) {
    sum[c][cell] += truth;
    n[c][cell] += 1.0;
    total_sum[cell] += truth;
    total_n[cell] += 1.0;
  }
  // The mean over clusters other than c; false when they have no sample in the cell.
  bool heldOut(std::size_t c, std::size_t cell, double* mean) const {
    const double count = total_n[cell] - n[c][cell];
    if (count <= 0.0) return false;
    *mean = (total_sum[cell] - sum[c][cell]) / count;
    return true;
  }
};

std::size_t cellOf(const std::array<std::vector<int>, kInputs>& b, std::size_t k, int bins,
                   int divisor) {
  std::size_t cell = 0;
  const int per = (bins + divisor - 1) / divisor;
  for (int f = 0; f < kInputs; ++f) cell = cell * per + static_cast<std::size_t>(b[f][k] / divisor);
  return cell;
}

// heldOutSquaredErrors with the samples' bins given.
std::vector<double> heldOutSquaredErrors(const std::vector<SpecularSample>& samples,
                                         const std::vector<std::size_t>& index,
                                         const std::vector<int>& cluster_of, std::size_t clusters,
                                         int bins, const Bins& b, const std::vector<float>& base) {
  std::size_t fine = 1, coarse = 1;
  for (int f = 0; f < kInputs; ++f) {
    fine *= static_cast<std::size_t>(bins);
    coarse *= static_cast<std::size_t>((bins + 1) / 2);
  }
  CellMeans fine_means(clusters, fine), coarse_means(clusters, coarse), all(clusters, 1);
  const auto clusterOf = [&](std::size_t k) {
    return static_cast<std::size_t>(cluster_of[static_cast<std::size_t>(samples[index[k]].scene)]);
  };
  const auto baseAt = [&](std::size_t k) {
    return base.empty() ? 0.0 : static_cast<double>(base[index[k]]);
  };
  for (std::size_t k = 0; k < index.size(); ++k) {
    const double truth = samples[index[k]].truth - baseAt(k);
    fine_means.add(clusterOf(k), cellOf(b, k, bins, 1), truth);
    coarse_means.add(clusterOf(k), cellOf(b, k, bins, 2), truth);
    all.add(clusterOf(k), 0, truth);
  }
  std::vector<double> out(index.size());
  for (std::size_t k = 0; k < index.size(); ++k) {
    const std::size_t c = clusterOf(k);
    double prediction = 0.0;
    if (!fine_means.heldOut(c, cellOf(b, k, bins, 1), &prediction) &&
        !coarse_means.heldOut(c, cellOf(b, k, bins, 2), &prediction)) {
      all.heldOut(c, 0, &prediction);
    }
    const double e = prediction + baseAt(k) - samples[index[k]].truth;
    out[k] = e * e;
  }
  return out;
}

}  // namespace

std::vector<double> heldOutSquaredErrors(const std::vector<SpecularSample>& samples,
                                         const std::vector<std::size_t>& index,
                                         const std::vector<int>& cluster_of, std::size_t clusters,
                                         int bins, const std::vector<float>& base) {
  return heldOutSquaredErrors(samples, index, cluster_of, clusters, bins,
                              binsOf(samples, index, {bins}).front(), base);
}

SoFloor soFloor(const std::vector<SpecularSample>& samples, const std::vector<int>& cluster_of,
                std::size_t clusters, std::size_t roughness, const std::vector<float>& base) {
  if (clusters < 2) throw Error("SO floor: needs at least 2 scenes to hold one out");
  std::vector<std::vector<std::size_t>> index(roughness);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    index[static_cast<std::size_t>(samples[i].roughness)].push_back(i);
  }
  constexpr std::size_t kChoices = std::size(kSoFloorBins);
  const std::size_t bases = base.empty() ? 1 : 2;
  // mse[base][choice][roughness], and the truth's mean noise variance per roughness.
  std::vector<std::vector<std::vector<double>>> mse(
      bases, std::vector<std::vector<double>>(kChoices, std::vector<double>(roughness, 0.0)));
  // The bins of every roughness and bin count, shared by both bases.
  const std::vector<int> counts(std::begin(kSoFloorBins), std::end(kSoFloorBins));
  std::vector<std::vector<Bins>> bins(roughness);
  tbb::parallel_for(std::size_t{0}, roughness,
                    [&](std::size_t j) { bins[j] = binsOf(samples, index[j], counts); });
  const std::vector<float> none;
  tbb::parallel_for(std::size_t{0}, bases * kChoices * roughness, [&](std::size_t task) {
    const std::size_t b = task / (kChoices * roughness), choice = (task / roughness) % kChoices,
                      j = task % roughness;
    const std::vector<double> e2 =
        heldOutSquaredErrors(samples, index[j], cluster_of, clusters, kSoFloorBins[choice],
                             bins[j][choice], b == 0 ? none : base);
    double sum = 0.0;
    for (double v : e2) sum += v;
    mse[b][choice][j] = sum / std::max<double>(1.0, static_cast<double>(e2.size()));
  });
  std::size_t best_b = 0, best = 0;
  double best_mse = -1.0;
  for (std::size_t b = 0; b < bases; ++b) {
    for (std::size_t choice = 0; choice < kChoices; ++choice) {
      double pooled = 0.0;
      for (std::size_t j = 0; j < roughness; ++j) pooled += mse[b][choice][j] * index[j].size();
      if (best_mse < 0.0 || pooled < best_mse) best_b = b, best = choice, best_mse = pooled;
    }
  }
  SoFloor out;
  out.bins = kSoFloorBins[best];
  out.on_base = best_b == 1;
  for (std::size_t j = 0; j < roughness; ++j) {
    double noise = 0.0;
    for (std::size_t i : index[j]) noise += samples[i].noise_var;
    noise /= std::max<double>(1.0, static_cast<double>(index[j].size()));
    out.rmse.push_back(std::sqrt(mse[best_b][best][j]));
    out.rmse_noise_corrected.push_back(std::sqrt(std::max(0.0, mse[best_b][best][j] - noise)));
  }
  for (const auto& row : mse[best_b]) {
    out.by_bins.emplace_back();
    for (double v : row) out.by_bins.back().push_back(std::sqrt(v));
  }
  return out;
}

}  // namespace gtbake
