// bench_validate_gtso: validate-gtso's hottest kernels on a real sweep (docs/performance.md),
// each beside the implementation it replaced, with the ratio and a check that both give the same
// bits:
//   - the cone SSE table of docs/validate_gtso.md §3 (2 laws x 49 values of log10 u over every
//     sample): baseline one pass over a (scene, roughness) group per grid value, as before; now
//     one pass per group scoring every grid value of both laws;
//   - the sign-flip tests of §2 with 48 scenes (2^20 drawn patterns per test): baseline a Philox
//     draw and one chain of 48 dependent additions per pattern; now the patterns drawn once and
//     summed 8 side by side;
// and the u fit (§3, both laws), the SO floor (§2a), wall and CPU seconds alone.
//
//   bench_validate_gtso SWEEP_DIR [--threads T]     (SWEEP_DIR: e.g. <out>/sweep of gtbake all,
//   a sweep with S channels)
#include <sys/resource.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <random>
#include <string>

#include "../bench_args.h"
#include "common/rng.h"
#include "common/threads.h"
#include "validate_gtso/cone_u_fit.h"
#include "validate_gtso/scene_paired_test.h"
#include "validate_gtso/scene_statistics.h"
#include "validate_gtso/so_floor.h"
#include "validate_gtso/specular_sweep.h"
#include "validate_gtso/u_scene_interval.h"

namespace {

using namespace gtbake;

double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
         1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

struct Timing {
  double wall = 0.0, cpu = 0.0;
};

template <typename F>
Timing timed(F&& f) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu = cpuSeconds();
  f();
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
          cpuSeconds() - cpu};
}

void row(const char* kernel, const Timing& base, const Timing& now, bool same) {
  std::printf("%-34s %9.2f %9.2f %9.2f %9.2f %8.2fx  %s\n", kernel, base.wall, base.cpu, now.wall,
              now.cpu, base.cpu / now.cpu, same ? "same bits" : "DIFFERENT");
}

// The table as it was computed before: one task per (law, cluster, roughness, grid value).
std::array<std::vector<double>, 2> baselineTable(const std::vector<SpecularSample>& samples,
                                                 const std::vector<int>& cluster_of,
                                                 std::size_t clusters, std::size_t roughness,
                                                 const std::vector<double>& log10_u) {
  std::vector<std::vector<std::vector<std::size_t>>> g(
      clusters, std::vector<std::vector<std::size_t>>(roughness));
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const SpecularSample& s = samples[i];
    if (s.r_p > 0.0f) g[cluster_of[s.scene]][s.roughness].push_back(i);
  }
  const std::size_t K = log10_u.size();
  std::array<std::vector<double>, 2> sse;
  for (int law = 0; law < 2; ++law) {
    sse[law].assign(clusters * roughness * K, 0.0);
    tbb::parallel_for(std::size_t{0}, clusters * roughness * K, [&](std::size_t task) {
      const std::size_t k = task % K, j = (task / K) % roughness, c = task / (K * roughness);
      if (g[c][j].empty()) return;
      const SpecularSample& first = samples[g[c][j].front()];
      const double w = law == 1 ? first.r_p : static_cast<double>(first.r_p) * first.r_p;
      const ConeAperture aperture = coneAperture(std::pow(10.0, log10_u[k]), w);
      double sum = 0.0;
      for (std::size_t i : g[c][j]) {
        const double e = coneAt(samples[i], aperture) - samples[i].truth;
        sum += e * e;
      }
      sse[law][task] = sum;
    });
  }
  return sse;
}

// The sign-flip p-value as it was computed before (drawn patterns, S > kExactSignFlipScenes).
double baselineSignFlip(const std::vector<double>& d) {
  double sum = 0.0, scale = 0.0;
  for (double v : d) sum += v, scale += std::abs(v);
  const double target = std::abs(sum) - 1e-12 * scale;
  const CounterRng rng(0x5167, d.size());
  const std::uint64_t hits = tbb::parallel_reduce(
      tbb::blocked_range<std::uint64_t>(0, kSignFlipDraws), std::uint64_t{0},
      [&](const tbb::blocked_range<std::uint64_t>& r, std::uint64_t n) {
        for (std::uint64_t k = r.begin(); k != r.end(); ++k) {
          const auto w = rng.words(k, 0);
          const std::uint64_t b = (std::uint64_t{w[0]} << 32) | w[1];
          double s = 0.0;
          for (std::size_t i = 0; i < d.size(); ++i) s += ((b >> i) & 1u) ? -d[i] : d[i];
          if (std::abs(s) >= target) ++n;
        }
        return n;
      },
      std::plus<>());
  return (static_cast<double>(hits) + 1.0) / (static_cast<double>(kSignFlipDraws) + 1.0);
}

}  // namespace

int main(int argc, char** argv) {
  const bench::BenchArgs args = bench::parseBenchArgs(argc, argv);
  const std::string& dir = args.path;
  const int threads = args.threads;
  if (dir.empty()) {
    std::fprintf(stderr, "usage: bench_validate_gtso SWEEP_DIR [--threads T]\n");
    return 2;
  }
  const ThreadLimit limit(threads);
  const SpecularSweep sweep = readSpecularSweep(dir);
  const std::vector<SpecularSample> samples = gatherSamples(sweep);
  std::vector<int> cluster_of;
  const std::size_t S = sceneClusters(sweep, cluster_of).size();
  const std::size_t R = sweep.roughness.size();
  std::printf("bench_validate_gtso: %s, %zu samples, %zu scenes, %d threads\n", dir.c_str(),
              samples.size(), S, limit.threads());
  std::printf("%-34s %9s %9s %9s %9s %9s\n", "kernel", "base wall", "base cpu", "now wall",
              "now cpu", "cpu ratio");

  ConeSseTable table;
  const Timing now_table = timed([&] { table = coneSseTable(samples, cluster_of, S, R); });
  std::array<std::vector<double>, 2> base;
  const Timing base_table =
      timed([&] { base = baselineTable(samples, cluster_of, S, R, table.log10_u); });
  bool same = true;
  for (int law = 0; law < 2; ++law) {
    std::size_t at = 0;
    for (const auto& cluster : table.sse[law])
      for (const auto& grid : cluster)
        for (double v : grid) same = same && std::memcmp(&v, &base[law][at++], sizeof v) == 0;
  }
  row("cone SSE table (2 x 49 u values)", base_table, now_table, same);

  std::mt19937 gen(7);
  std::normal_distribution<double> normal(0.002, 0.01);
  std::vector<std::vector<double>> tests(8, std::vector<double>(S));
  for (auto& d : tests)
    for (double& v : d) v = normal(gen);
  std::vector<double> p_base, p_now;
  const Timing base_flip = timed([&] {
    for (const auto& d : tests) p_base.push_back(baselineSignFlip(d));
  });
  const std::vector<double> zero(S, 0.0);
  const Timing now_flip = timed([&] {
    for (const auto& d : tests) p_now.push_back(pairedSignFlip(d, zero).p_value);
  });
  row("sign-flip tests (8, 2^20 patterns)", base_flip, now_flip, p_base == p_now);

  UFits fits[2];
  const Timing fit = timed([&] {
    fits[0] = fitConeU(samples, false, &table);
    fits[1] = fitConeU(samples, true, &table);
  });
  std::printf("%-34s %9s %9s %9.2f %9.2f\n", "u fit (2 laws x 2 subsets)", "", "", fit.wall,
              fit.cpu);
  for (int law = 0; law < 2; ++law) {
    for (const UFit* f : {&fits[law].all, &fits[law].rp_ge_0_3}) {
      std::printf("  %-10s %-9s u %.12g rmse %.12g within 5%% [%.12g, %.12g]\n",
                  law == 0 ? "alpha" : "perceptual", f == &fits[law].all ? "all" : "r_p>=0.3", f->u,
                  f->rmse, f->low, f->high);
    }
  }
  const Timing floor = timed([&] { soFloor(samples, cluster_of, S, R); });
  std::printf("%-34s %9s %9s %9.2f %9.2f\n", "SO floor (one base)", "", "", floor.wall, floor.cpu);
  return same && p_base == p_now ? 0 : 1;
}
