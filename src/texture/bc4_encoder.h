// Exact-optimum BC4_UNORM encoder (docs/export.md §2).
//
// Contract. For a 4×4 block of targets v_t (clamped to [0, 1], NaN rejected), the encoder returns
// the endpoint pair (red_0, red_1) ∈ [0, 255]² and indices minimising
//     E(red_0, red_1) = Σ_{t = 0..15, row-major} min_k (p_k − v_t)²,
// p_k the D3D float palette (bc4_block.h), every term and the sum in double, summed in row-major
// texel order. Both endpoint modes are covered because the mode is red_0 > red_1 or not: all
// 65,536 pairs are candidates. Ties in E go to the lowest key red_0·256 + red_1; each texel takes
// the lowest palette code among equally near entries. The result is the exact optimum (checked
// against exhaustive search in tests/export/bc4_encoder_test.cpp) and does not depend on the CPU,
// the thread count or the compiler's vector width: only IEEE float/double +, −, ×, / and
// comparisons, no reassociation (-ffp-contract=off, no -ffast-math).
//
// Search (docs/export.md "Optimality argument"): branch and bound over the pairs, never dropping a
// pair that could tie or beat the best so far (E_best). With δ = √E_best (255-units, widened by a
// 1e-3 margin for the float palette's rounding), a candidate keeps every texel within δ of its
// palette. The interpolated entries lie on the ramp lo + m·(hi − lo)/n (n = 7 or 5), so for an
// anchor texel u and a fixed lo the admissible hi form the intervals
//     hi ∈ [lo + n·(u − δ − lo)/m, lo + n·(u + δ − lo)/m]      (m ≥ 1; m = 0 leaves hi free),
// kept as a 256-bit mask per lo. Bounds applied per lo: the extreme texels' masks; a spacing bound
// (a ramp cell between the extreme anchors cannot be wider than the largest texel gap + 2δ); a
// counting bound (no 3 texels may each exceed E_best/3). Survivors are scored with early exit and
// compared exactly (E, then key).
#pragma once

#include <cstdint>
#include <vector>

#include "common/progress.h"
#include "texture/bc4_block.h"

namespace gtbake {

struct Bc4Encoding {
  Bc4Block block{};
  double error = 0.0;  // E above: Σ squared error of the 16 decoded texels vs the clamped targets
};

class Bc4Encoder {
 public:
  // Tabulates the palettes of all 65,536 endpoint pairs (4 MiB of doubles), once per encoder.
  Bc4Encoder();

  // `texels`: 16 floats, row-major. Throws gtbake::Error on NaN.
  Bc4Encoding encodeBlock(const float* texels) const;

 private:
  struct Search;  // one block's targets and best pair so far
  double pairError(int key, const double* v) const;
  double boundedError(int key, const double* v, const int* order, double bound) const;
  void consider(Search& s, int key) const;
  void searchEightValueMode(Search& s) const;
  void searchSixValueMode(Search& s) const;

  std::vector<double> palettes_;  // [key = red_0·256 + red_1][code]
};

// A BC4-compressed volume: blocks over (x, y) of each z slice, in memory order (z slices, rows of
// blocks, blocks left to right), plus the error of the decoded texels against the float input.
struct Bc4Volume {
  std::vector<std::uint8_t> bytes;
  double rmse = 0.0;     // over all texels, against the unclamped float input
  double max_abs = 0.0;  // largest |decoded − input|
  double seconds = 0.0;
};

// `data`: width·height·depth floats, x fastest. width and height must be multiples of 4. Parallel
// over slices with TBB; the bytes and the errors do not depend on the thread count.
Bc4Volume encodeBc4Volume(const Bc4Encoder& encoder, const float* data, int width, int height,
                          int depth, Progress* progress);

// The encoding of the same volume with texture x and y swapped, without running the encoder: each
// block of `src` (a height x width x depth encoding) transposed, endpoints kept and the 4x4
// indices transposed; `data` (width x height x depth, x fastest) is the swapped volume, against
// which rmse and max_abs are summed as encodeBc4Volume sums them. The exact encoder's error is a
// sum over the same 16 squared terms, so its optimum is the transposed block up to the summation
// order of ties; tests/export/bc4_encoder_test.cpp checks byte equality with encodeBc4Volume.
Bc4Volume swapBc4VolumeXY(const Bc4Volume& src, const float* data, int width, int height,
                          int depth);

// Decodes a volume written by encodeBc4Volume back to floats (x fastest).
std::vector<float> decodeBc4Volume(const std::uint8_t* bytes, int width, int height, int depth);

}  // namespace gtbake
