// bench_gtso: accuracy and time of the GTSO table bake (docs/gtso.md §5: every texel within 2.5e-4
// of a converged reference with >= 16x the samples; both tables in under 20 s on 2 cores).
//
// Bakes S3 and S4 with the default integrator resolution and again with `factor` times the cells
// per axis (factor^2 times the lobe samples; default 4 -> 16x), over ALL texels, and prints the
// max / RMS difference, the number of texels over the bar, and both bake times. Writes error maps
// (max over the other axes, viridis, 0..bar) into --out if given.
//
// usage: bench_gtso [--cells N] [--factor F] [--threads T] [--size N] [--dims 3|4] [--out DIR]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "common/image_io.h"
#include "common/progress.h"
#include "common/threads.h"
#include "gtso/gtso_integrator.h"
#include "gtso/gtso_tables.h"

using namespace gtbake;
using namespace gtbake::gtso;

namespace {

constexpr double kBar = 2.5e-4;  // docs/gtso.md §5

struct Options {
  int cells = kDefaultLobeCells, factor = 4, threads = 2, size = 32, dims = 0;  // 0: both
  std::string out;
};

Table bake(int dims, const Options& o, int cells, double& seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  Progress progress(
      "bench_gtso: " + std::to_string(dims) + "D at " + std::to_string(cells) + " cells",
      static_cast<std::uint64_t>(o.size) * o.size);
  Table t = bakeTable(dims, o.size, cells, &progress);
  progress.finish();
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return t;
}

// Error map over (A, r_p): max |error| over the other axes.
void writeErrorMap(const std::string& path, const Table& a, const Table& b) {
  const int n = a.size;
  std::vector<float> map(static_cast<std::size_t>(n) * n, 0.f);
  for (std::size_t i = 0; i < a.values.size(); ++i) {
    const int A = static_cast<int>(i % n), r = static_cast<int>((i / (n * n)) % n);
    const float e = static_cast<float>(std::abs(a.values[i] - b.values[i]));
    float& m = map[static_cast<std::size_t>(n - 1 - r) * n + A];
    m = std::max(m, e);
  }
  writePng(path, n, n, 3, toViridis8(map, 0.f, static_cast<float>(kBar)));
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--cells")
      o.cells = std::atoi(v.c_str());
    else if (k == "--factor")
      o.factor = std::atoi(v.c_str());
    else if (k == "--threads")
      o.threads = std::atoi(v.c_str());
    else if (k == "--size")
      o.size = std::atoi(v.c_str());
    else if (k == "--dims")
      o.dims = std::atoi(v.c_str());
    else if (k == "--out")
      o.out = v;
    else {
      std::fprintf(stderr, "bench_gtso: unknown option %s\n", k.c_str());
      return 1;
    }
  }
  const ThreadLimit limit(o.threads);
  std::printf("bench_gtso: %d threads, cells %d (x%d for the reference = %dx samples)\n",
              limit.threads(), o.cells, o.factor, o.factor * o.factor);
  std::printf("%-4s %10s %10s %12s %12s %10s %10s\n", "tab", "bake_s", "ref_s", "max_err",
              "rms_err", "over_bar", "texels");
  double bakeTotal = 0.0;
  for (int dims : {3, 4}) {
    if (o.dims != 0 && dims != o.dims) continue;
    double tb = 0.0, tr = 0.0;
    const Table t = bake(dims, o, o.cells, tb);
    const Table r = bake(dims, o, o.cells * o.factor, tr);
    bakeTotal += tb;
    double mx = 0.0, ss = 0.0;
    std::size_t over = 0;
    for (std::size_t i = 0; i < t.values.size(); ++i) {
      const double e = std::abs(t.values[i] - r.values[i]);
      mx = std::max(mx, e);
      ss += e * e;
      over += e > kBar;
    }
    std::printf("%-4s %10.2f %10.2f %12.3e %12.3e %10zu %10zu\n", dims == 3 ? "3d" : "4d", tb, tr,
                mx, std::sqrt(ss / t.values.size()), over, t.values.size());
    if (!o.out.empty()) {
      writeErrorMap(o.out + "/gtso" + std::to_string(dims) + "d_error_vs_reference.png", t, r);
    }
  }
  std::printf("both tables: %.2f s (bar: 20 s on 2 cores)\n", bakeTotal);
  return 0;
}
