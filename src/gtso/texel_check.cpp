#include "gtso/texel_check.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "common/error.h"
#include "common/rng.h"

namespace gtbake::gtso {

std::vector<std::size_t> sampleLines(int dims, int size, int count, std::uint64_t seed) {
  const std::size_t total = static_cast<std::size_t>(size) * size;
  if (count < 1 || static_cast<std::size_t>(count) > total) {
    throw Error("texel check: the line count must be in [1, " + std::to_string(total) + "]");
  }
  // Partial Fisher-Yates: position k swaps with a uniform position in [k, total).
  std::vector<std::size_t> order(total);
  std::iota(order.begin(), order.end(), std::size_t{0});
  const CounterRng rng(seed, static_cast<std::uint64_t>(dims));
  for (int k = 0; k < count; ++k) {
    const std::uint32_t w = rng.words(static_cast<std::uint64_t>(k), 0)[0];
    const std::size_t span = total - static_cast<std::size_t>(k);
    const std::size_t j = static_cast<std::size_t>(k) + static_cast<std::size_t>(w) % span;
    std::swap(order[static_cast<std::size_t>(k)], order[j]);
  }
  order.resize(static_cast<std::size_t>(count));
  std::sort(order.begin(), order.end());
  return order;
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
  double sum2 = 0.0;
  for (std::size_t line : lines) {
    for (const std::array<int, 4>& i : lineTexels(t.dims, t.size, line)) {
      const std::size_t at = t.index(i);
      const double d = std::abs(t.values[at] - ref.values[at]);
      sum2 += d * d;
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
  return c;
}

}  // namespace gtbake::gtso
