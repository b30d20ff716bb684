// Adequacy of the cubic and the monotone 2D table (docs/profiles.md §8).
//
// The cubic is adequate when its in-sample RMSE of G is within kAdequacyRatio of the floor of any
// function of (Â, ρ) (fit_floor.h): a more flexible function of the same inputs could then gain at
// most that much. The table is the alternative: G at kTableNodes values of Â (0, 1/(N−1), ..., 1)
// × the sweep's albedos, looked up bilinearly (linear in Â between nodes, linear in ρ between
// albedos, ρ clamped to the albedo range). Per albedo, each point goes to its nearest Â node; the
// node values are the weighted isotonic (non-decreasing) regression of the nodes' mean G with the
// nodes' point counts as weights, by pool-adjacent-violators, clipped to [0, 1], and the last node
// is 1 (G(1, ρ) = 1). Nodes without points take the linear interpolation of their neighbours (or
// the nearest value at an end). Every row is then non-decreasing in Â with G(1) = 1, and so is
// every ρ between rows.
#pragma once

#include <cstddef>
#include <vector>

#include "fit/sweep_data.h"

namespace gtbake {

inline constexpr int kTableNodes = 32;
inline constexpr double kAdequacyRatio = 1.05;  // cubic RMSE / floor RMSE at most this

// Weighted least-squares non-decreasing fit to y with weights w > 0 (pool adjacent violators).
std::vector<double> isotonicRegression(const std::vector<double>& y, const std::vector<double>& w);

struct ProfileTable {
  std::vector<double> rhos;    // the albedo nodes
  int nodes = kTableNodes;     // Â nodes
  std::vector<double> values;  // [albedo][Â node], row-major
  // The shipped lookup, gtsoMultiBounceTable of runtime/gtso_runtime.h, in double.
  double lookup(double A, double rho) const;
};

// Per-node point counts and G sums, [albedo][node] for the sums; additive over views.
struct TableSums {
  std::vector<double> count;
  std::vector<std::vector<double>> sum;
  TableSums& operator+=(const TableSums& other);
};

int tableNode(double A, int nodes = kTableNodes);
// [view] the sums of its points.
std::vector<TableSums> viewTableSums(const SweepData& data);
ProfileTable fitProfileTable(const TableSums& sums, const std::vector<double>& albedos);

// RMSE of G over every point and albedo with view s scored by tables[table_of[s]].
double tableRmse(const SweepData& data, const std::vector<ProfileTable>& tables,
                 const std::vector<std::size_t>& table_of);

struct TableFit {
  ProfileTable table;
  double rmse = 0.0;           // in sample
  double held_out_rmse = 0.0;  // each scene scored by the table fitted without it
  bool held_out = false;       // false: fewer than two scenes
};
TableFit tableFit(const SweepData& data);

}  // namespace gtbake
