#include "texture/bc4_encoder.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <tuple>

#include "common/error.h"

namespace gtbake {
namespace {

// Pruning slack in 255-units: the float palette sits within ~1e-4 of the real-valued ramp
// lo + m·(hi − lo)/n, so widening δ by 1e-3 keeps every pruning test conservative.
constexpr double kDeltaMargin255 = 1e-3;
// Relative slack for early exit: a partial sum taken in another texel order may differ from the
// row-major sum by a few ulps; only partial sums clearly above the best are discarded.
constexpr double kBoundSlack = 1e-9;
constexpr int kPairs = 256 * 256;  // every (red_0, red_1)

// 256-bit set of candidate hi endpoints.
struct HiMask {
  std::uint64_t words[4] = {0, 0, 0, 0};

  void setRange(double lower, double upper) {
    if (upper < 0.0 || lower > 255.0 || lower > upper) return;
    // ceil and floor of values clamped to [-1, 256]: the truncation toward zero, corrected by
    // one where it landed on the wrong side (exact for every double in that range).
    const double x = std::max(lower, -1.0), y = std::min(upper, 256.0);
    int a = static_cast<int>(x), b = static_cast<int>(y);
    a += a < x ? 1 : 0;
    b -= b > y ? 1 : 0;
    setRange(std::max(a, 0), std::min(b, 255));
  }
  void setRange(int a, int b) {
    for (int w = a >> 6; a <= b && w <= (b >> 6); ++w) {
      const int first = std::max(a, w * 64) - w * 64;
      const int last = std::min(b, w * 64 + 63) - w * 64;
      // Bits first..last; 2 << 63 wraps to 0, so last = 63 gives the all-ones high part.
      words[w] |= ((2ull << last) - 1) & (~0ull << first);
    }
  }
  void intersect(const HiMask& other) {
    for (int w = 0; w < 4; ++w) words[w] &= other.words[w];
  }
  bool empty() const { return (words[0] | words[1] | words[2] | words[3]) == 0; }
  int count() const {
    return __builtin_popcountll(words[0]) + __builtin_popcountll(words[1]) +
           __builtin_popcountll(words[2]) + __builtin_popcountll(words[3]);
  }
  int first() const {  // lowest set bit; mask must not be empty
    for (int w = 0;; ++w) {
      if (words[w] != 0) return w * 64 + __builtin_ctzll(words[w]);
    }
  }
  int last() const {  // highest set bit; mask must not be empty
    for (int w = 3;; --w) {
      if (words[w] != 0) return w * 64 + 63 - __builtin_clzll(words[w]);
    }
  }
  template <typename F>
  void forEach(F&& f) const {
    for (int w = 0; w < 4; ++w) {
      for (std::uint64_t bits = words[w]; bits != 0; bits &= bits - 1) {
        f(w * 64 + __builtin_ctzll(bits));
      }
    }
  }
};

// The hi ∈ [hmin, hmax] (hmin ≥ lo) that keep anchor u (255-units) within δ of some point of the
// ramp lo + m·(hi − lo)/n, m = 0..n. Point m = 0 is lo itself and leaves hi free; points m ≥ 1
// give the intervals of the header comment, and only the m whose interval can meet
// [hmin, hmax] are visited (the m range is widened by one on each side against rounding).
// 1/k for k = 0..255 (entry 0 unused): the interval bounds below multiply instead of dividing.
// The product differs from the quotient by < 1 ulp, far inside the 1e-3 margin of δ.
struct Reciprocals {
  double of[256];
  constexpr Reciprocals() : of() {
    for (int k = 1; k < 256; ++k) of[k] = 1.0 / k;
  }
};
constexpr Reciprocals kReciprocal;

HiMask anchorMask(double u, int lo, int n, double delta, int hmin, int hmax) {
  HiMask mask;
  if (std::fabs(lo - u) <= delta) {
    mask.setRange(hmin, hmax);
    return mask;
  }
  if (u + delta < lo) return mask;            // every ramp point is ≥ lo
  const double below = n * (u - delta - lo);  // > 0 here
  const double above = n * (u + delta - lo);
  const int m_first =
      std::max(1, static_cast<int>(below * kReciprocal.of[std::max(hmax - lo, 1)]) - 1);
  const int m_last =
      hmin > lo ? std::min(n, static_cast<int>(above * kReciprocal.of[hmin - lo]) + 2) : n;
  for (int m = m_first; m <= m_last; ++m) {
    mask.setRange(std::max(lo + below * kReciprocal.of[m], static_cast<double>(hmin)),
                  std::min(lo + above * kReciprocal.of[m], static_cast<double>(hmax)));
  }
  return mask;
}

double deltaOf(double best) {
  return std::sqrt(best) * 255.0 * (1.0 + kBoundSlack) + kDeltaMargin255;
}

// Counting bound: if j texels each have error > best/j, the block's error exceeds best. A texel
// with error ≤ best/j lies within r_j = deltaOf(best/j) of the ramp (or, with `has01`, of 0 or 1).
// Removes from `mask` every hi for which at least j texels are outside their radius; the counts
// are kept bit-sliced (counter[k] = "more than k texels outside").
// j = 3 ran fewest instructions of the level sets {2}, {3}, {4}, {2,4}, {2,8} (callgrind).
constexpr int kCountLevel = 3;
constexpr int kMaxCountLevel = kCountLevel;
// The block's extreme texels (order[0], order[1]) are intersected at radius δ first; the counting
// bound then covers all 16 texels. More radius-δ anchors cost more masks than they save.
constexpr int kPlainAnchors = 2;
// With this few candidates left, scoring them directly is cheaper than the counting bound's masks.
constexpr int kDirectScoreCandidates = 32;  // callgrind: 32 beat 0, 2, 4, 8, 16 and 64

void pruneByCount(HiMask& mask, const double* u, int lo, int n, bool has01, double best, int j) {
  const double radius = deltaOf(best / j);
  HiMask counter[kMaxCountLevel];
  const int hmin = mask.first(), hmax = mask.last();
  for (int t = 0; t < kBc4BlockTexels; ++t) {
    if (has01 && std::min(u[t], 255.0 - u[t]) <= radius) continue;  // 0 or 1 is near enough
    const HiMask near = anchorMask(u[t], lo, n, radius, hmin, hmax);
    for (int k = j - 1; k >= 0; --k) {
      for (int w = 0; w < 4; ++w) {
        const std::uint64_t outside = ~near.words[w];
        counter[k].words[w] |= (k == 0 ? outside : counter[k - 1].words[w] & outside);
      }
    }
  }
  for (int w = 0; w < 4; ++w) mask.words[w] &= ~counter[j - 1].words[w];
}

}  // namespace

Bc4Encoder::Bc4Encoder() : palettes_(static_cast<std::size_t>(kPairs) * 8) {
  for (int key = 0; key < kPairs; ++key) {
    const Bc4Palette p = bc4Palette(key >> 8, key & 255);
    for (int k = 0; k < 8; ++k) palettes_[static_cast<std::size_t>(key) * 8 + k] = p[k];
  }
}

namespace {

// Two palette entries (or two squared distances) per lane pair.
using Lanes2 = double __attribute__((vector_size(16)));

// The palette of one key as four lane pairs.
struct PaletteLanes {
  Lanes2 p[4];
  explicit PaletteLanes(const double* palette) { std::memcpy(p, palette, sizeof(p)); }
};

// min_k (p_k − x)² over the 8 entries. Each square is the same IEEE product as in the scalar
// loop; the minimum of non-NaN squares (never −0) is one value whatever order it is taken in, so
// the lane-wise min tree returns exactly the scalar loop's result.
inline double nearestSquare(const PaletteLanes& pal, double x) {
  const Lanes2 xx = {x, x};
  Lanes2 d[4];
  for (int i = 0; i < 4; ++i) d[i] = (pal.p[i] - xx) * (pal.p[i] - xx);
  const Lanes2 m01 = d[1] < d[0] ? d[1] : d[0];
  const Lanes2 m23 = d[3] < d[2] ? d[3] : d[2];
  const Lanes2 m = m23 < m01 ? m23 : m01;
  return std::min(m[0], m[1]);
}

}  // namespace

double Bc4Encoder::pairError(int key, const double* v) const {
  const PaletteLanes pal(&palettes_[static_cast<std::size_t>(key) * 8]);
  double sum = 0.0;
  for (int t = 0; t < kBc4BlockTexels; ++t) sum += nearestSquare(pal, v[t]);
  return sum;
}

// The same terms as pairError, in `order`, stopping once the sum exceeds `bound`.
double Bc4Encoder::boundedError(int key, const double* v, const int* order, double bound) const {
  const PaletteLanes pal(&palettes_[static_cast<std::size_t>(key) * 8]);
  double sum = 0.0;
  for (int i = 0; i < kBc4BlockTexels && sum <= bound; ++i) sum += nearestSquare(pal, v[order[i]]);
  return sum;
}

// One block's search: targets (clamped, and in 255-units for the bounds), texel orders and the
// best pair so far.
struct Bc4Encoder::Search {
  double v[kBc4BlockTexels];
  double u[kBc4BlockTexels];
  int sorted[kBc4BlockTexels];  // texels by increasing value
  int order[kBc4BlockTexels];   // extremes first: min, max, 2nd min, 2nd max, ...
  double best = std::numeric_limits<double>::infinity();
  int best_key = kPairs;
  // Zero error at the lowest key: nothing can beat it.
  bool exact() const { return best == 0.0 && best_key == 0; }
};

void Bc4Encoder::consider(Search& s, int key) const {
  const double bound = s.best * (1.0 + kBoundSlack);
  if (boundedError(key, s.v, s.order, bound) > bound) return;
  const double e = pairError(key, s.v);
  if (e < s.best || (e == s.best && key < s.best_key)) {
    s.best = e;
    s.best_key = key;
  }
}

// 8-value mode: red_0 = hi > red_1 = lo, palette = the ramp with n = 7. Every texel must be within
// δ of the ramp: lo ≤ umin + δ and hi ≥ umax − δ because the ramp spans [lo, hi]; the extreme
// texels' masks are intersected and the counting bound covers all 16. Spacing bound: when
// umax − umin > 2δ, umin and umax sit near different ramp points, so every ramp cell between them
// has its open middle (p_k + δ, p_k+1 − δ) inside [umin, umax] and free of texels: its length
// (hi − lo)/n − 2δ cannot exceed the largest gap between consecutive sorted texels.
void Bc4Encoder::searchEightValueMode(Search& s) const {
  const double* u = s.u;
  const double umin = u[s.sorted[0]];
  const double umax = u[s.sorted[kBc4BlockTexels - 1]];
  double gap = 0.0;
  for (int i = 1; i < kBc4BlockTexels; ++i) {
    gap = std::max(gap, u[s.sorted[i]] - u[s.sorted[i - 1]]);
  }
  for (int lo = 0; lo <= 254 && !s.exact(); ++lo) {
    const double delta = deltaOf(s.best);
    if (lo > umin + delta) break;
    const double span = umax - umin > 2.0 * delta ? 7.0 * (gap + 2.0 * delta) : 255.0;
    if (lo + span < umax - delta) continue;
    HiMask mask;
    mask.setRange(std::max(static_cast<double>(lo + 1), umax - delta), lo + span);
    for (int i = 0; i < kPlainAnchors && !mask.empty(); ++i) {
      mask.intersect(anchorMask(u[s.order[i]], lo, 7, delta, mask.first(), mask.last()));
    }
    if (mask.count() > kDirectScoreCandidates) {
      pruneByCount(mask, u, lo, 7, false, s.best, kCountLevel);
    }
    mask.forEach([&](int hi) { consider(s, hi * 256 + lo); });
  }
}

// 6-value mode: red_0 = lo ≤ red_1 = hi, palette = the ramp with n = 5 plus 0 and 1. A texel
// farther than δ from both 0 and 1 must use the ramp: those are the anchors (the smallest and
// largest are intersected at radius δ, the counting bound covers the rest; spacing bound as in
// the 8-value mode). Without anchors: key 0 scores F = Σ min(v, 1 − v)², every pair scores ≤ F,
// and a pair scores exactly F (losing the tie to key 0) unless the ramp brings some texel t
// strictly nearer than √f_t — so the candidates are the union over t of those ramp conditions.
void Bc4Encoder::searchSixValueMode(Search& s) const {
  const double* u = s.u;
  const double* v = s.v;
  double f[kBc4BlockTexels];
  for (int t = 0; t < kBc4BlockTexels; ++t) {
    f[t] = std::min(v[t] * v[t], (1.0 - v[t]) * (1.0 - v[t]));
  }
  for (int lo = 0; lo <= 255 && !s.exact(); ++lo) {
    const double delta = deltaOf(s.best);
    int first = -1;
    int last = -1;
    double anchor_gap = 0.0;  // largest gap between consecutive anchors
    for (int i = 0; i < kBc4BlockTexels; ++i) {
      const double x = u[s.sorted[i]];
      if (std::min(x, 255.0 - x) > delta) {
        if (first < 0) first = s.sorted[i];
        if (last >= 0) anchor_gap = std::max(anchor_gap, x - u[last]);
        last = s.sorted[i];
      }
    }
    HiMask mask;
    if (first >= 0) {
      if (lo > u[first] + delta) break;
      const double span =
          u[last] - u[first] > 2.0 * delta ? 5.0 * (anchor_gap + 2.0 * delta) : 255.0;
      if (lo + span < u[last] - delta) continue;
      mask.setRange(std::max(static_cast<double>(lo), u[last] - delta), lo + span);
      mask.intersect(anchorMask(u[first], lo, 5, delta, lo, 255));
      if (!mask.empty()) {
        mask.intersect(anchorMask(u[last], lo, 5, delta, mask.first(), mask.last()));
      }
      if (mask.count() > kDirectScoreCandidates) {
        pruneByCount(mask, u, lo, 5, true, s.best, kCountLevel);
      }
    } else {
      const double e0 = palettes_[static_cast<std::size_t>(lo) * 256 * 8];  // lo/255.0f
      for (int t = 0; t < kBc4BlockTexels; ++t) {
        if (f[t] == 0.0) continue;  // exactly 0 or 1: nothing improves on it
        if ((e0 - v[t]) * (e0 - v[t]) < f[t]) {
          mask.setRange(lo, 255);
          break;
        }
        const double radius = deltaOf(std::min(f[t], s.best));
        for (int m = 1; m <= 5; ++m) {
          mask.setRange(lo + 5 * (u[t] - radius - lo) / m, lo + 5 * (u[t] + radius - lo) / m);
        }
      }
      HiMask valid;
      valid.setRange(lo, 255);
      mask.intersect(valid);
    }
    mask.forEach([&](int hi) { consider(s, lo * 256 + hi); });
  }
}

Bc4Encoding Bc4Encoder::encodeBlock(const float* texels) const {
  Search s;
  for (int t = 0; t < kBc4BlockTexels; ++t) {
    if (std::isnan(texels[t])) throw Error("BC4 encoder: input texel is NaN");
    s.v[t] = std::min(std::max(static_cast<double>(texels[t]), 0.0), 1.0);
    s.u[t] = s.v[t] * 255.0;
  }
  std::iota(s.sorted, s.sorted + kBc4BlockTexels, 0);
  std::stable_sort(s.sorted, s.sorted + kBc4BlockTexels,
                   [&](int a, int b) { return s.v[a] < s.v[b]; });
  for (int i = 0; i < kBc4BlockTexels / 2; ++i) {
    s.order[2 * i] = s.sorted[i];
    s.order[2 * i + 1] = s.sorted[kBc4BlockTexels - 1 - i];
  }

  // Key 0 = (0, 0) in the 6-value mode: palette {0, 0, 0, 0, 0, 0, 0, 1}. If it is exact, nothing
  // can beat it (lowest key, zero error).
  consider(s, 0);
  // Seeds: endpoints bracketing the block's range, in both modes, to start with a small δ.
  const double umin = s.u[s.sorted[0]];
  const double umax = s.u[s.sorted[kBc4BlockTexels - 1]];
  for (const int lo : {static_cast<int>(std::floor(umin)), static_cast<int>(std::ceil(umin))}) {
    for (const int hi : {static_cast<int>(std::floor(umax)), static_cast<int>(std::ceil(umax))}) {
      if (hi > lo) consider(s, hi * 256 + lo);
      consider(s, lo * 256 + hi);
    }
  }
  searchEightValueMode(s);
  searchSixValueMode(s);

  const int red0 = s.best_key >> 8;
  const int red1 = s.best_key & 255;
  const Bc4Palette palette = bc4Palette(red0, red1);
  std::array<std::uint8_t, 16> indices{};
  for (int t = 0; t < kBc4BlockTexels; ++t) {
    double nearest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 8; ++k) {
      const double d = (palette[k] - s.v[t]) * (palette[k] - s.v[t]);
      if (d < nearest) {
        nearest = d;
        indices[t] = static_cast<std::uint8_t>(k);
      }
    }
  }
  return {packBc4Block(red0, red1, indices), s.best};
}

namespace {

// The 16 texels of block b (z slice, row, column of blocks) of a width x height volume.
void blockTexels(const float* data, int width, int height, std::size_t b, float* texels) {
  const int bx = width / 4, by = height / 4;
  const std::size_t z = b / (static_cast<std::size_t>(bx) * by);
  const int row = static_cast<int>(b / bx % by);
  const int col = static_cast<int>(b % bx);
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      texels[4 * j + i] =
          data[(z * height + 4 * row + j) * static_cast<std::size_t>(width) + 4 * col + i];
    }
  }
}

// rmse and max_abs of a volume from its per-block squared-error sums and maxima, blocks in order.
void sumBlockErrors(const std::vector<double>& block_sse, const std::vector<double>& block_max,
                    Bc4Volume* volume) {
  double sse = 0.0;
  for (std::size_t b = 0; b < block_sse.size(); ++b) {
    sse += block_sse[b];
    volume->max_abs = std::max(volume->max_abs, block_max[b]);
  }
  volume->rmse = std::sqrt(sse / static_cast<double>(block_sse.size() * kBc4BlockTexels));
}

// Σ (decoded − texel)² and max |decoded − texel| of one block, row-major.
std::pair<double, double> blockError(const std::uint8_t* block, const float* texels) {
  const std::array<float, 16> decoded = decodeBc4Block(block);
  double sse = 0.0;
  double worst = 0.0;
  for (int t = 0; t < kBc4BlockTexels; ++t) {
    const double d = static_cast<double>(decoded[t]) - texels[t];
    sse += d * d;
    worst = std::max(worst, std::fabs(d));
  }
  return {sse, worst};
}

// A volume built block by block (`make(b, texels)` gives block b of the 16 texels), with the
// errors of the decoded texels against `data` summed per block and then in block order.
template <class MakeBlock>
Bc4Volume buildVolume(const float* data, int width, int height, int depth, Progress* progress,
                      const MakeBlock& make) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t blocks = static_cast<std::size_t>(width / 4) * (height / 4) * depth;
  Bc4Volume volume;
  volume.bytes.resize(blocks * kBc4BlockBytes);
  std::vector<double> block_sse(blocks);
  std::vector<double> block_max(blocks);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks), [&](const auto& range) {
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      float texels[kBc4BlockTexels];
      blockTexels(data, width, height, b, texels);
      const Bc4Block block = make(b, texels);
      std::copy(block.begin(), block.end(), &volume.bytes[b * kBc4BlockBytes]);
      std::tie(block_sse[b], block_max[b]) = blockError(block.data(), texels);
    }
    if (progress) progress->add(range.size());
  });
  sumBlockErrors(block_sse, block_max, &volume);
  volume.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return volume;
}

}  // namespace

Bc4Volume encodeBc4Volume(const Bc4Encoder& encoder, const float* data, int width, int height,
                          int depth, Progress* progress) {
  return buildVolume(data, width, height, depth, progress, [&](std::size_t, const float* texels) {
    return encoder.encodeBlock(texels).block;
  });
}

Bc4Volume swapBc4VolumeXY(const Bc4Volume& src, const float* data, int width, int height,
                          int depth) {
  const int bx = width / 4, by = height / 4;
  return buildVolume(data, width, height, depth, nullptr, [&](std::size_t b, const float*) {
    const std::size_t z = b / (static_cast<std::size_t>(bx) * by);
    const int row = static_cast<int>(b / bx % by), col = static_cast<int>(b % bx);
    // The source volume is height x width: this block is its block (row = col, col = row).
    const std::size_t s = (z * bx + col) * by + row;
    const std::uint8_t* in = &src.bytes[s * kBc4BlockBytes];
    std::uint64_t bits = 0;
    for (int i = 0; i < 6; ++i) bits |= static_cast<std::uint64_t>(in[2 + i]) << (8 * i);
    std::array<std::uint8_t, 16> indices{};
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < 4; ++i) indices[4 * j + i] = (bits >> (3 * (4 * i + j))) & 7u;
    }
    return packBc4Block(in[0], in[1], indices);
  });
}

std::vector<float> decodeBc4Volume(const std::uint8_t* bytes, int width, int height, int depth) {
  const int bx = width / 4;
  const int by = height / 4;
  std::vector<float> out(static_cast<std::size_t>(width) * height * depth);
  for (std::size_t b = 0; b < static_cast<std::size_t>(bx) * by * depth; ++b) {
    const std::size_t z = b / (static_cast<std::size_t>(bx) * by);
    const int row = static_cast<int>(b / bx % by);
    const int col = static_cast<int>(b % bx);
    const std::array<float, 16> texels = decodeBc4Block(bytes + b * kBc4BlockBytes);
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < 4; ++i) {
        out[(z * height + 4 * row + j) * static_cast<std::size_t>(width) + 4 * col + i] =
            texels[4 * j + i];
      }
    }
  }
  return out;
}

}  // namespace gtbake
