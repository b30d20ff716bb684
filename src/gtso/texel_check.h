// The texel error of a baked table against a finer reference, measured on a seeded random sample
// of its lines in every `gtbake gtso` run (docs/gtso.md §5).
//
// A line is one integrator lobe (r_p texel, theta_o texel): 3D the N texels of A at that
// (theta_o, r_p), 4D the N x N texels of (A, beta). Each sampled line is re-integrated with
// `factor` x the lobe cells per side (factor^2 x the rectangles; 4 gives 16x) through
// the same bakeTable code, and every texel of the line is compared with the table. The full
// reference (`--reference-factor`) is the same comparison over all N^2 lines.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gtso/gtso_tables.h"  // also declares gtbake::Progress

namespace gtbake::gtso {

inline constexpr int kTexelCheckFactor = 4;  // cells per side of the reference: 16x rectangles
// The edge stratum: lines whose theta_o texel is within this many of either end (normal view and
// grazing, where the refined theta_o axis crowds its texels and the quadrature is hardest).
inline constexpr int kTexelCheckEdgeColumns = 3;

struct TexelStratum {
  std::size_t lines = 0, texels = 0;
  double max = 0.0, rms = 0.0;
};

struct TexelCheck {
  int factor = kTexelCheckFactor;
  int reference_cells = 0;
  std::uint64_t seed = 0;
  std::vector<std::size_t> lines;    // sampled lines (r_p texel * N + theta_o texel), ascending
  std::size_t texels = 0;            // texels compared
  double max = 0.0, rms = 0.0;       // |table - reference| over those texels
  std::array<int, 4> worst_index{};  // texel (x, y, z, w) of the largest error
  GtsoPoint worst{};                 // its physical parameters
  double worst_value = 0.0, worst_reference = 0.0;
  double seconds = 0.0;    // wall time of the re-integration
  TexelStratum strata[2];  // [edge, interior] (isEdgeLine)
};

// `count` distinct lines of an N x N line grid, uniform without replacement, ascending;
// deterministic in seed (and distinct streams for 3D and 4D).
std::vector<std::size_t> sampleLines(int dims, int size, int count, std::uint64_t seed);
// The sample of every run: half the lines (rounded up) from the edge stratum and the rest from
// the interior, each uniform without replacement (a stratum too small gives its remainder to the
// other); every line when count >= N^2. Ascending, deterministic in seed.
std::vector<std::size_t> sampleStratifiedLines(int dims, int size, int count, std::uint64_t seed);
bool isEdgeLine(int size, std::size_t line);  // theta_o texel < k or >= N - k

// Re-integrates `lines` of t at cells * factor and compares every texel on them.
TexelCheck checkTexels(const Table& t, int cells, int factor, const std::vector<std::size_t>& lines,
                       std::uint64_t seed, Progress* progress);

// The texels of line `line` in table order (index arrays), 3D N texels, 4D N x N.
std::vector<std::array<int, 4>> lineTexels(int dims, int size, std::size_t line);

}  // namespace gtbake::gtso
