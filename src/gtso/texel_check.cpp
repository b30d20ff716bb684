#include "gtso/texel_check.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "common/error.h"
#include "common/rng.h"

namespace gtbake::gtso {

namespace {

// `count` distinct entries of `pool`, uniform without replacement (partial Fisher-Yates).
std::vector<std::size_t> samplePool(std::vector<std::size_t> pool, std::size_t count,
                                    const CounterRng& rng) {
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t w = rng.words(static_cast<std::uint64_t>(k), 0)[0];
    const std::size_t j = k + static_cast<std::size_t>(w) % (pool.size() - k);
    std::swap(pool[k], pool[j]);
  }
  pool.resize(count);
  return pool;
}

}  // namespace

bool isEdgeLine(int size, std::size_t line) {
  const int th = static_cast<int>(line % static_cast<std::size_t>(size));
  return th < kTexelCheckEdgeColumns || th >= size - kTexelCheckEdgeColumns;
}

std::vector<std::size_t> sampleLines(int dims, int size, int count, std::uint64_t seed) {
  const std::size_t total = static_cast<std::size_t>(size) * size;
  if (count < 1 || static_cast<std::size_t>(count) > total) {
    throw Error("texel check: the line count must be in [1, " + std::to_string(total) + "]");
  }
  std::vector<std::size_t> all(total);
  std::iota(all.begin(), all.end(), std::size_t{0});
  std::vector<std::size_t> out = samplePool(std::move(all), static_cast<std::size_t>(count),
                                            CounterRng(seed, static_cast<std::uint64_t>(dims)));
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::size_t> sampleStratifiedLines(int dims, int size, int count, std::uint64_t seed) {
  const std::size_t total = static_cast<std::size_t>(size) * size;
  if (count < 1) throw Error("texel check: the line count must be at least 1");
  std::vector<std::size_t> edge, interior;
  for (std::size_t l = 0; l < total; ++l) (isEdgeLine(size, l) ? edge : interior).push_back(l);
  const std::size_t n = std::min(static_cast<std::size_t>(count), total);
  std::size_t fromEdge = std::min((n + 1) / 2, edge.size());
  const std::size_t fromInterior = std::min(n - fromEdge, interior.size());
  fromEdge = n - fromInterior;  // the interior's shortfall goes to the edge
  std::vector<std::size_t> out = samplePool(
      std::move(edge), fromEdge, CounterRng(seed, 16 + static_cast<std::uint64_t>(dims)));
  const std::vector<std::size_t> in = samplePool(
      std::move(interior), fromInterior, CounterRng(seed, 32 + static_cast<std::uint64_t>(dims)));
  out.insert(out.end(), in.begin(), in.end());
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::array<int, 4>> lineTexels(int dims, int size, std::size_t line) {
  // bakeTable's line numbering: r = line / N (z), theta_o = line % N (3D y, 4D w).
  const int r = static_cast<int>(line / static_cast<std::size_t>(size));
  const int th = static_cast<int>(line % static_cast<std::size_t>(size));
  std::vector<std::array<int, 4>> texels;
  for (int k = 0; k < (dims == 3 ? 1 : size); ++k) {
    for (int a = 0; a < size; ++a) {
      texels.push_back(dims == 3 ? std::array<int, 4>{a, th, r, 0}
                                 : std::array<int, 4>{a, k, r, th});
    }
  }
  return texels;
}

TexelCheck checkTexels(const Table& t, int cells, int factor, const std::vector<std::size_t>& lines,
                       std::uint64_t seed, Progress* progress) {
  TexelCheck c;
  c.factor = factor;
  c.reference_cells = cells * factor;
  c.seed = seed;
  c.lines = lines;
  const auto start = std::chrono::steady_clock::now();
  const Table ref = bakeTable(t.dims, t.size, c.reference_cells, progress, &lines);
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  double sum2 = 0.0, stratumSum2[2] = {0.0, 0.0};
  for (std::size_t line : lines) {
    const int k = isEdgeLine(t.size, line) ? 0 : 1;
    TexelStratum& st = c.strata[k];
    ++st.lines;
    for (const std::array<int, 4>& i : lineTexels(t.dims, t.size, line)) {
      const std::size_t at = t.index(i);
      const double d = std::abs(t.values[at] - ref.values[at]);
      sum2 += d * d;
      stratumSum2[k] += d * d;
      st.max = std::max(st.max, d);
      ++st.texels;
      ++c.texels;
      if (d > c.max || c.texels == 1) {
        c.max = d;
        c.worst_index = i;
        c.worst = t.point(i);
        c.worst_value = t.values[at];
        c.worst_reference = ref.values[at];
      }
    }
  }
  c.rms = c.texels > 0 ? std::sqrt(sum2 / static_cast<double>(c.texels)) : 0.0;
  for (int k = 0; k < 2; ++k) {
    TexelStratum& st = c.strata[k];
    st.rms = st.texels > 0 ? std::sqrt(stratumSum2[k] / static_cast<double>(st.texels)) : 0.0;
  }
  return c;
}

}  // namespace gtbake::gtso
