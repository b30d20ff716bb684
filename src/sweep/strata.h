// Stratified draws within a half-sample estimate: the one grid the walks' first bounce and the
// specular samples use (docs/sweep.md §2).
//
// A half holds n = N/2 draws of sample indices of one parity (s = 2t + h, h the half). Draw t is
// placed uniformly in cell t of an a × b grid over [0,1)² (a·b = n, a the largest divisor of n not
// above √n): u ← ((column + u0)/a, (row + u1)/b). Every cell has the same area, and the maps that
// follow (concentric disk, VNDF) preserve area up to a constant density, so each draw is still
// marginally distributed as an unstratified one: each half stays unbiased, the two halves stay
// independent (separate jitters), and the variance is no larger (proportional allocation over
// equal-probability strata).
#pragma once

#include <cmath>

namespace gtbake {

class StratumGrid {
 public:
  // Grid for draws_per_half ≥ 1 draws.
  explicit StratumGrid(int draws_per_half) {
    columns_ = static_cast<int>(std::sqrt(static_cast<double>(draws_per_half)));
    while (columns_ > 1 && draws_per_half % columns_ != 0) --columns_;
    if (columns_ < 1) columns_ = 1;
    rows_ = draws_per_half / columns_;
  }
  int columns() const { return columns_; }
  int rows() const { return rows_; }
  // Cell (column, row) of sample s (draw t = s >> 1 of its half).
  float column(int s) const { return static_cast<float>((s >> 1) % columns_); }
  float row(int s) const { return static_cast<float>((s >> 1) / columns_); }

 private:
  int columns_ = 1;
  int rows_ = 1;
};

// u ∈ [0,1) moved into cell `cell` of `cells` equal cells.
inline float stratum(float cell, float u, int cells) {
  return (cell + u) / static_cast<float>(cells);
}

}  // namespace gtbake
