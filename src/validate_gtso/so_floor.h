// The floor of specular occlusion from the runtime's inputs (docs/validate_gtso.md §5): how well
// the best function of (A, b·n, b·ωr, n·ωr, r_p) can predict the path-traced S on scenes it was not
// fitted on. Every runtime method (the tables, the cone, Lagarde) is such a function, so no method
// can beat this floor on new content except by the floor estimator's own limits.
//
// Estimator: at each roughness (r_p fixed), a binned regressor on the other four inputs — each
// input cut into `bins` equal-count bins (edges from every sample's inputs, no truth used), the
// prediction in a cell is the mean truth of the cell's samples from the other scene clusters
// (leave one cluster out), falling back to the cell of half the bins and then to the other
// clusters' mean where a cell is empty. The regressor is fitted to the truth itself and, with a
// base function given (the 4D float table, itself a function of the same inputs), to the truth
// minus the base, the prediction then adding the base back; bins per input and base are chosen
// from kSoFloorBins × {none, base} by the RMSE pooled over every roughness (one choice, reported).
#pragma once

#include <cstddef>
#include <vector>

#include "validate_gtso/specular_methods.h"

namespace gtbake {

// (Not kFloorBins: that name is the fit floor's in fit_floor.h, and two inline variables of one
// name in one namespace are one variable to the linker.)
inline constexpr int kSoFloorBins[] = {4, 6, 8, 12, 16};

struct SoFloor {
  int bins = 0;                              // the chosen bins per input
  bool on_base = false;                      // the regressor corrects the base function
  std::vector<double> rmse;                  // [roughness], held-out scenes
  std::vector<double> rmse_noise_corrected;  // [roughness], √max(0, MSE − mean noise var)
  std::vector<std::vector<double>> by_bins;  // [kSoFloorBins index][roughness], chosen base
};

// cluster_of[scene]: its cluster; fewer than 2 clusters is a gtbake::Error.
// base: empty or base[i] at samples[i].
SoFloor soFloor(const std::vector<SpecularSample>& samples, const std::vector<int>& cluster_of,
                std::size_t clusters, std::size_t roughness, const std::vector<float>& base = {});

// The held-out squared errors of one roughness's samples `index` for `bins` (exposed for tests).
std::vector<double> heldOutSquaredErrors(const std::vector<SpecularSample>& samples,
                                         const std::vector<std::size_t>& index,
                                         const std::vector<int>& cluster_of, std::size_t clusters,
                                         int bins, const std::vector<float>& base = {});

}  // namespace gtbake
