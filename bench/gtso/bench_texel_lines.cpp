// bench_texel_lines: where the bake's texel error against a 16x reference is largest (docs/gtso.md
// §5, "Texel check in every run"). Re-integrates a set of table lines (one integrator lobe each:
// an (r_p texel, theta_o texel) pair) with 4x the lobe cells per side through the bake code
// (gtso/texel_check.h) and prints the max, the worst texel, the texels over 1.6e-4 and 2.5e-4,
// and the max per r_p row and per theta_o column.
//
// usage: bench_texel_lines [--dims 3|4] [--lines all|edges] [--size N] [--threads T]
//   all:   every line (3D: ~1 min on 2 cores; 4D: ~16x a 4D bake)
//   edges: r_p rows 0-4 and theta_o columns N-4..N-1 in full, plus every 8th row and column
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>

#include "common/threads.h"
#include "gtso/gtso_integrator.h"
#include "gtso/gtso_tables.h"
#include "gtso/texel_check.h"

using namespace gtbake;
using namespace gtbake::gtso;

int main(int argc, char** argv) {
  int dims = 3, size = 32, threads = 2;
  std::string which = "all";
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--dims"))
      dims = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--lines"))
      which = argv[i + 1];
    else if (!std::strcmp(argv[i], "--size"))
      size = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--threads"))
      threads = std::atoi(argv[i + 1]);
  }
  const ThreadLimit limit(threads);
  std::vector<std::size_t> lines;
  for (int r = 0; r < size; ++r)
    for (int th = 0; th < size; ++th) {
      const bool edge = r <= 4 || th >= size - 4 || (r % 8 == 4 && th % 8 == 3);
      if (which == "all" || edge) lines.push_back(static_cast<std::size_t>(r) * size + th);
    }
  const Table t = bakeTable(dims, size, kDefaultLobeCells, nullptr, &lines);
  const Table ref = bakeTable(dims, size, kDefaultLobeCells * kTexelCheckFactor, nullptr, &lines);
  std::map<int, double> byRow, byColumn;
  int over16 = 0, over25 = 0;
  std::size_t texels = 0;
  double max = 0.0, sum2 = 0.0;
  std::array<int, 4> w{};
  for (std::size_t l : lines)
    for (const auto& i : lineTexels(dims, size, l)) {
      const double d = std::abs(t.values[t.index(i)] - ref.values[t.index(i)]);
      byRow[i[2]] = std::max(byRow[i[2]], d);
      const int column = dims == 3 ? i[1] : i[3];
      byColumn[column] = std::max(byColumn[column], d);
      over16 += d > 1.6e-4;
      over25 += d > 2.5e-4;
      sum2 += d * d;
      if (d > max || texels == 0) {
        max = d;
        w = i;
      }
      ++texels;
    }
  const GtsoPoint p = t.point(w);
  std::printf("%dD, %zu lines (%s), %zu texels vs %dx reference: max %.3g rms %.3g\n", dims,
              lines.size(), which.c_str(), texels, kTexelCheckFactor * kTexelCheckFactor, max,
              std::sqrt(sum2 / static_cast<double>(texels)));
  std::printf("  worst texel (%d %d %d %d): A %.6g beta %.5f r_p %.5f theta_o %.5f, %.6g vs %.6g\n",
              w[0], w[1], w[2], w[3], p.A, p.beta, p.r_p, p.theta_o, t.values[t.index(w)],
              ref.values[t.index(w)]);
  std::printf("  texels > 1.6e-4: %d, > 2.5e-4: %d\n  max by r_p row:", over16, over25);
  for (const auto& [k, v] : byRow) std::printf(" %d:%.2g", k, v);
  std::printf("\n  max by theta_o column:");
  for (const auto& [k, v] : byColumn) std::printf(" %d:%.2g", k, v);
  std::printf("\n");
  return 0;
}
