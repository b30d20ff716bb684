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

// Whether the samples `a` and `b` have the same inputs in the same order.
bool sameInputs(const std::vector<SpecularSample>& samples, const std::vector<std::size_t>& a,
                const std::vector<std::size_t>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (inputs(samples[a[k]]) != inputs(samples[b[k]])) return false;
  }
  return true;
}

std::size_t cellOf(const std::array<std::vector<int>, kInputs>& b, std::size_t k, int bins,
                   int divisor) {
  std::size_t cell = 0;
  const int per = (bins + divisor - 1) / divisor;
  for (int f = 0; f < kInputs; ++f) cell = cell * per + static_cast<std::size_t>(b[f][k] / divisor);
  return cell;
}

// Sums and counts of the truth per cell over every cluster, and over the one cluster being held
// out; `heldOut` is the mean over the other clusters. The held-out cluster's sums are gathered
// one cluster at a time in sample order (the order of one array per cluster, so the same sums)
// and cleared after, so memory is a few arrays of cells rather than clusters × cells.
struct CellMeans {
  std::vector<double> total_sum, total_n, own_sum, own_n;
  explicit CellMeans(std::size_t cells)
      : total_sum(cells, 0.0), total_n(cells, 0.0), own_sum(cells, 0.0), own_n(cells, 0.0) {}
  void addTotal(std::size_t cell, double truth) {
    total_sum[cell] += truth;
    total_n[cell] += 1.0;
  }
  void addOwn(std::size_t cell, double truth) {
    own_sum[cell] += truth;
    own_n[cell] += 1.0;
  }
  void clearOwn(std::size_t cell) { own_sum[cell] = own_n[cell] = 0.0; }
  // The mean over the other clusters; false when they have no sample in the cell.
  bool heldOut(std::size_t cell, double* mean) const {
    const double count = total_n[cell] - own_n[cell];
    if (count <= 0.0) return false;
    *mean = (total_sum[cell] - own_sum[cell]) / count;
    return true;
  }
};

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
  CellMeans fine_means(fine), coarse_means(coarse), all(1);
  const auto baseAt = [&](std::size_t k) {
    return base.empty() ? 0.0 : static_cast<double>(base[index[k]]);
  };
  // Each sample's truth less the base, its cells, and the samples of each cluster in order.
  std::vector<double> truth(index.size());
  std::vector<std::size_t> fine_cell(index.size()), coarse_cell(index.size());
  std::vector<std::vector<std::size_t>> members(clusters);
  for (std::size_t k = 0; k < index.size(); ++k) {
    truth[k] = samples[index[k]].truth - baseAt(k);
    fine_cell[k] = cellOf(b, k, bins, 1);
    coarse_cell[k] = cellOf(b, k, bins, 2);
    members[static_cast<std::size_t>(cluster_of[static_cast<std::size_t>(samples[index[k]].scene)])]
        .push_back(k);
    fine_means.addTotal(fine_cell[k], truth[k]);
    coarse_means.addTotal(coarse_cell[k], truth[k]);
    all.addTotal(0, truth[k]);
  }
  std::vector<double> out(index.size());
  for (const std::vector<std::size_t>& own : members) {
    for (std::size_t k : own) {
      fine_means.addOwn(fine_cell[k], truth[k]);
      coarse_means.addOwn(coarse_cell[k], truth[k]);
      all.addOwn(0, truth[k]);
    }
    for (std::size_t k : own) {
      double prediction = 0.0;
      if (!fine_means.heldOut(fine_cell[k], &prediction) &&
          !coarse_means.heldOut(coarse_cell[k], &prediction)) {
        all.heldOut(0, &prediction);
      }
      const double e = prediction + baseAt(k) - samples[index[k]].truth;
      out[k] = e * e;
    }
    for (std::size_t k : own) {
      fine_means.clearOwn(fine_cell[k]);
      coarse_means.clearOwn(coarse_cell[k]);
    }
    all.clearOwn(0);
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
  // The inputs are the pixel's, so every roughness of a sweep (each pixel at every roughness, in
  // one order) has the same input sequence: bins of equal sequences are equal (the same sort of
  // the same values), so they are computed once and shared.
  std::vector<std::size_t> same_as(roughness);
  for (std::size_t j = 0; j < roughness; ++j) {
    same_as[j] = j;
    for (std::size_t o = 0; o < j && same_as[j] == j; ++o) {
      if (same_as[o] == o && sameInputs(samples, index[j], index[o])) same_as[j] = o;
    }
  }
  std::vector<std::vector<Bins>> bins(roughness);
  tbb::parallel_for(std::size_t{0}, roughness, [&](std::size_t j) {
    if (same_as[j] == j) bins[j] = binsOf(samples, index[j], counts);
  });
  const std::vector<float> none;
  tbb::parallel_for(std::size_t{0}, bases * kChoices * roughness, [&](std::size_t task) {
    const std::size_t b = task / (kChoices * roughness), choice = (task / roughness) % kChoices,
                      j = task % roughness;
    const std::vector<double> e2 =
        heldOutSquaredErrors(samples, index[j], cluster_of, clusters, kSoFloorBins[choice],
                             bins[same_as[j]][choice], b == 0 ? none : base);
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
