#include "validate_gtso/scene_paired_test.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <numeric>

#include "common/error.h"
#include "common/rng.h"

namespace gtbake {

namespace {

// |Σ ±d_s| ≥ |Σ d_s| counts with this relative slack (the observed pattern itself must count).
constexpr double kTieSlack = 1e-12;

// Scenes per partial-sum table: a pattern's byte of sign bits picks one of 256 precomputed sums.
constexpr std::size_t kTableScenes = 8;

// signFlipCountAtLeast with pattern k's word w given by `bits(k, w)`. Each pattern's sum adds its
// ⌈S/8⌉ table entries in byte order (a different rounding from adding scene by scene, far below
// kTieSlack), and the count is an integer, so the result does not depend on how the patterns are
// split across threads.
template <typename Bits>
std::uint64_t countAtLeast(const std::vector<double>& d, double target, std::uint64_t patterns,
                           Bits&& bits) {
  const std::size_t S = d.size(), bytes = (S + kTableScenes - 1) / kTableScenes;
  // table[b][i]: Σ ±d over the scenes of byte b, scene b·8 + j negated when bit j of i is set;
  // bits past the last scene select nothing, so the last byte needs no mask.
  std::vector<double> table(bytes * 256);
  for (std::size_t b = 0; b < bytes; ++b) {
    const std::size_t n = std::min(kTableScenes, S - b * kTableScenes);
    for (std::size_t i = 0; i < 256; ++i) {
      double sum = 0.0;
      for (std::size_t j = 0; j < n; ++j) {
        const double v = d[b * kTableScenes + j];
        sum += (i >> j) & 1u ? -v : v;
      }
      table[b * 256 + i] = sum;
    }
  }
  return tbb::parallel_reduce(
      tbb::blocked_range<std::uint64_t>(0, patterns), std::uint64_t{0},
      [&](const tbb::blocked_range<std::uint64_t>& r, std::uint64_t hits) {
        for (std::uint64_t k = r.begin(); k != r.end(); ++k) {
          double sum = 0.0;
          for (std::size_t b = 0; b < bytes; ++b) {
            const std::uint64_t word = bits(k, b / 8);
            sum += table[b * 256 + ((word >> (8 * (b % 8))) & 0xffu)];
          }
          hits += std::abs(sum) >= target ? 1 : 0;
        }
        return hits;
      },
      std::plus<>());
}

// The kSignFlipDraws random sign patterns of S scenes (stream S of seed 0x5167; word w of pattern
// k from counter (k, w), so S ≤ 64 draws the one word it always did), drawn once per S and shared
// by every test of a run: a ranking runs dozens of tests on the same scenes. [pattern][word].
const std::vector<std::uint64_t>& drawnPatterns(std::size_t S) {
  static std::mutex mutex;
  static std::map<std::size_t, std::vector<std::uint64_t>> drawn;
  const std::lock_guard<std::mutex> lock(mutex);
  std::vector<std::uint64_t>& patterns = drawn[S];
  const std::size_t words = (S + 63) / 64;
  if (patterns.empty()) {
    patterns.resize(kSignFlipDraws * words);
    const CounterRng rng(0x5167, S);
    tbb::parallel_for(std::size_t{0}, patterns.size(), [&](std::size_t i) {
      const auto w = rng.words(i / words, static_cast<std::uint32_t>(i % words));
      patterns[i] = (std::uint64_t{w[0]} << 32) | w[1];
    });
  }
  return patterns;
}

std::string pText(double p) {
  char text[32];
  std::snprintf(text, sizeof(text), p < 0.001 ? "%.1e" : "%.3f", p);
  return text;
}

}  // namespace

std::uint64_t signFlipCountAtLeast(const std::vector<double>& d, double target,
                                   const std::uint64_t* drawn, std::uint64_t patterns) {
  if (drawn == nullptr) {
    return countAtLeast(d, target, patterns, [](std::uint64_t k, std::size_t) { return k; });
  }
  const std::size_t words = (d.size() + 63) / 64;
  return countAtLeast(d, target, patterns,
                      [&](std::uint64_t k, std::size_t w) { return drawn[k * words + w]; });
}

PairedTest pairedSignFlip(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size()) throw Error("paired test: the two methods have different scenes");
  if (x.size() < 2) throw Error("paired test: needs at least 2 scenes");
  if (x.size() > kMaxPairedScenes) {
    throw Error("paired test: at most " + std::to_string(kMaxPairedScenes) + " scenes");
  }
  const std::size_t S = x.size();
  std::vector<double> d(S);
  for (std::size_t s = 0; s < S; ++s) d[s] = x[s] - y[s];
  PairedTest out;
  out.scenes = S;
  const double sum = std::accumulate(d.begin(), d.end(), 0.0);
  out.mean_difference = sum / static_cast<double>(S);
  double ss = 0.0;
  for (double v : d) ss += (v - out.mean_difference) * (v - out.mean_difference);
  const double sd = std::sqrt(ss / static_cast<double>(S - 1));
  out.t = sd > 0.0 ? out.mean_difference / (sd / std::sqrt(static_cast<double>(S))) : 0.0;
  double scale = 0.0;
  for (double v : d) scale += std::abs(v);
  if (scale == 0.0) return out;  // identical: p = 1
  const double target = std::abs(sum) - kTieSlack * scale;
  if (S <= kExactSignFlipScenes) {
    const std::uint64_t patterns = std::uint64_t{1} << S;
    out.p_value = static_cast<double>(signFlipCountAtLeast(d, target, nullptr, patterns)) /
                  static_cast<double>(patterns);
  } else {
    const std::uint64_t hits =
        signFlipCountAtLeast(d, target, drawnPatterns(S).data(), kSignFlipDraws);
    out.p_value = (static_cast<double>(hits) + 1.0) / (static_cast<double>(kSignFlipDraws) + 1.0);
  }
  out.significant = out.p_value < kSignificance;
  return out;
}

RankingTest rankingTest(const std::vector<std::string>& names,
                        const std::vector<std::vector<double>>& per_scene,
                        const std::vector<double>& pooled) {
  std::vector<std::size_t> order(names.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return pooled[a] < pooled[b]; });
  RankingTest out;
  out.best = names[order.front()];
  for (std::size_t k = 1; k < order.size(); ++k) {
    out.others.push_back(names[order[k]]);
    out.vs_best.push_back(pairedSignFlip(per_scene[order[k]], per_scene[order.front()]));
    if (!(out.vs_best.back().significant && out.vs_best.back().mean_difference > 0.0)) {
      out.tied.push_back(names[order[k]]);
    }
  }
  out.statement = out.best + " has the lowest RMSE";
  if (out.tied.empty()) {
    out.statement += " and beats every other method at the scene level";
  } else {
    out.statement += "; at the scene level it is not distinguishable from ";
    for (std::size_t k = 0; k < out.tied.size(); ++k) {
      const auto it = std::find(out.others.begin(), out.others.end(), out.tied[k]);
      out.statement +=
          (k ? ", " : "") + out.tied[k] +
          " (p = " + pText(out.vs_best[static_cast<std::size_t>(it - out.others.begin())].p_value) +
          ")";
    }
  }
  out.statement += ".";
  return out;
}

}  // namespace gtbake
