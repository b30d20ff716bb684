#include "fit/profile_table.h"

#include <algorithm>
#include <cmath>

#include "fit/scene_jackknife.h"
#include "runtime/gtso_runtime.h"

namespace gtbake {

std::vector<double> isotonicRegression(const std::vector<double>& y, const std::vector<double>& w) {
  // Blocks of pooled values: their mean, weight and length, merged while they decrease.
  std::vector<double> mean, weight;
  std::vector<std::size_t> length;
  for (std::size_t i = 0; i < y.size(); ++i) {
    mean.push_back(y[i]);
    weight.push_back(w[i]);
    length.push_back(1);
    while (mean.size() > 1 && mean[mean.size() - 2] > mean.back()) {
      const std::size_t b = mean.size() - 1;
      const double total = weight[b - 1] + weight[b];
      mean[b - 1] = (weight[b - 1] * mean[b - 1] + weight[b] * mean[b]) / total;
      weight[b - 1] = total;
      length[b - 1] += length[b];
      mean.pop_back();
      weight.pop_back();
      length.pop_back();
    }
  }
  std::vector<double> out;
  for (std::size_t b = 0; b < mean.size(); ++b) out.insert(out.end(), length[b], mean[b]);
  return out;
}

double ProfileTable::lookup(double A, double rho) const {
  return gtsoMultiBounceTable(rhos.data(), values.data(), static_cast<int>(rhos.size()), nodes, A,
                              rho);
}

TableSums& TableSums::operator+=(const TableSums& other) {
  for (std::size_t i = 0; i < count.size(); ++i) count[i] += other.count[i];
  for (std::size_t j = 0; j < sum.size(); ++j) {
    for (std::size_t i = 0; i < sum[j].size(); ++i) sum[j][i] += other.sum[j][i];
  }
  return *this;
}

int tableNode(double A, int nodes) {
  return static_cast<int>(std::lround(std::clamp(A, 0.0, 1.0) * (nodes - 1)));
}

namespace {

TableSums zeroSums(std::size_t albedos) {
  TableSums t;
  t.count.assign(kTableNodes, 0.0);
  t.sum.assign(albedos, std::vector<double>(kTableNodes, 0.0));
  return t;
}

}  // namespace

std::vector<TableSums> viewTableSums(const SweepData& data) {
  std::vector<TableSums> out(data.scenes.size(), zeroSums(data.albedos.size()));
  for (std::size_t s = 0; s < data.scenes.size(); ++s) {
    TableSums& t = out[s];
    for (std::size_t i = data.scenes[s].begin; i < data.scenes[s].end; ++i) {
      const int node = tableNode(data.full.A[i]);
      t.count[node] += 1.0;
      for (std::size_t j = 0; j < data.albedos.size(); ++j) t.sum[j][node] += data.full.G[j][i];
    }
  }
  return out;
}

namespace {

// One albedo's row: isotonic regression of the occupied nodes' means (the last node fixed at 1),
// clipped to [0, 1], empty nodes interpolated.
std::vector<double> tableRow(const std::vector<double>& count, const std::vector<double>& sum) {
  const int last = kTableNodes - 1;
  std::vector<int> occupied;
  std::vector<double> y, w;
  for (int i = 0; i < last; ++i) {
    if (count[i] <= 0.0) continue;
    occupied.push_back(i);
    y.push_back(sum[i] / count[i]);
    w.push_back(count[i]);
  }
  std::vector<double> row(kTableNodes, 0.0);
  std::vector<int> known;
  const std::vector<double> fitted = isotonicRegression(y, w);
  for (std::size_t k = 0; k < occupied.size(); ++k) {
    row[occupied[k]] = std::clamp(fitted[k], 0.0, 1.0);
    known.push_back(occupied[k]);
  }
  row[last] = 1.0;
  known.push_back(last);
  for (int i = 0; i < known.front(); ++i) row[i] = row[known.front()];
  for (std::size_t k = 0; k + 1 < known.size(); ++k) {
    const int lo = known[k], hi = known[k + 1];
    for (int i = lo + 1; i < hi; ++i) {
      row[i] = row[lo] + (row[hi] - row[lo]) * (i - lo) / static_cast<double>(hi - lo);
    }
  }
  return row;
}

}  // namespace

ProfileTable fitProfileTable(const TableSums& sums, const std::vector<double>& albedos) {
  ProfileTable t;
  t.rhos = albedos;
  for (std::size_t j = 0; j < albedos.size(); ++j) {
    const std::vector<double> row = tableRow(sums.count, sums.sum[j]);
    t.values.insert(t.values.end(), row.begin(), row.end());
  }
  return t;
}

double tableRmse(const SweepData& data, const std::vector<ProfileTable>& tables,
                 const std::vector<std::size_t>& table_of) {
  double sum2 = 0.0;
  for (std::size_t s = 0; s < data.scenes.size(); ++s) {
    const ProfileTable& t = tables[table_of[s]];
    for (std::size_t j = 0; j < data.albedos.size(); ++j) {
      for (std::size_t i = data.scenes[s].begin; i < data.scenes[s].end; ++i) {
        const double e = data.full.G[j][i] - t.lookup(data.full.A[i], data.albedos[j]);
        sum2 += e * e;
      }
    }
  }
  return std::sqrt(sum2 / static_cast<double>(data.points() * data.albedos.size()));
}

TableFit tableFit(const SweepData& data) {
  const std::vector<TableSums> views = viewTableSums(data);
  TableSums total = zeroSums(data.albedos.size());
  for (const TableSums& v : views) total += v;
  TableFit out;
  out.table = fitProfileTable(total, data.albedos);
  out.rmse = tableRmse(data, {out.table}, std::vector<std::size_t>(data.scenes.size(), 0));
  const Grouping groups = groupByScene(data);
  if (groups.names.size() < 2) return out;
  std::vector<ProfileTable> held_out;
  for (std::size_t c = 0; c < groups.names.size(); ++c) {
    TableSums rest = zeroSums(data.albedos.size());
    for (std::size_t s = 0; s < views.size(); ++s) {
      if (groups.of[s] != c) rest += views[s];
    }
    held_out.push_back(fitProfileTable(rest, data.albedos));
  }
  out.held_out_rmse = tableRmse(data, held_out, groups.of);
  out.held_out = true;
  return out;
}

}  // namespace gtbake
