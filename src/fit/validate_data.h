// What `validate` needs from a fit, small enough to ship (docs/fit.md §10): the refit, its
// Monte Carlo covariance, the leave-one-scene-out and leave-one-type-out refits with their
// simulated thresholds, the floor, and per view binned power sums of the points.
//
// Every error `validate` reports is a sum over points of a polynomial in A and G, so sums per
// view and per bin of A give it exactly, for any constants. With p(A) = aA³ − bA² + cA at
// albedo ρ_j and a bin's points i,
//   Σ_i (G_ij − p(A_i))² = Σ G² − 2(c Σ G A − b Σ G A² + a Σ G A³) + Σ_{m,n} p_m p_n Σ A^(m+n),
//   Σ_i (p(A_i) − q(A_i))²  = Σ_{m,n} d_m d_n Σ A^(m+n),   d = p − q,
// so each bin keeps Σ A^k (k = 0..6; k = 0 counts the points) and, per albedo, Σ G, Σ G²,
// Σ G A, Σ G A², Σ G A³. The bins (kValidateBins of width 0.05 in A) put the verdict's ranges of
// A (0.3, 0.7) on bin edges, so every per-range figure is exact too. Sums are accumulated in
// long double per view in point order, so they do not depend on the thread count.
//
// `gtbake fit` writes it as validate_data.json in its output set; `validate --luts DIR` reads it
// back (verified against fit.manifest.json) and answers without the sweep's images, and
// `validate --sweep DIR` builds the same data from the images: both give the same report.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fit/fit_analysis.h"
#include "fit/multibounce_coeffs.h"
#include "fit/scene_jackknife.h"

namespace gtbake {

// The file `gtbake fit` writes beside fit.json, in its output set.
inline constexpr const char* kValidateDataFile = "validate_data.json";
inline constexpr int kValidateBins = 20;  // bins of width 0.05 in A
inline constexpr int kPowerSums = 7;      // Σ A^k, k = 0..6
inline constexpr int kGSums = 5;          // Σ G, Σ G², Σ G·A, Σ G·A², Σ G·A³

struct BinSums {
  std::array<double, kPowerSums> power{};          // Σ A^k
  std::vector<std::array<double, kGSums>> albedo;  // [albedo] the G sums
};

struct ViewSums {
  std::string name;           // the view (image)
  std::string scene;          // its scene (the jackknife's unit)
  std::string type;           // its scene type
  double weight_share = 0.0;  // its share of the fit's weight
  std::vector<BinSums> bins;  // kValidateBins
  double floor_rmse = 0.0;    // the view's floor RMSE (fit_floor.h)
};

struct ValidateData {
  std::string source;  // where it came from, for the summary
  int spp = 0;
  int bounces = 0;
  std::vector<double> albedos;
  FitSettings settings;
  std::string input;  // "ray-traced" or the estimator whose Â the fit read
  MultiBounceCoeffs refit{};
  MultiBounceCoeffs mc_se{};
  std::array<double, 36> mc_covariance{};
  SceneJackknife scene_jackknife;
  SceneJackknife type_jackknife;
  std::vector<double> floor_per_albedo;  // floor RMSE per albedo
  double floor_rmse = 0.0;
  std::vector<ViewSums> views;
  std::size_t points() const;
};

// The data of an analysis: the sums from its points, the rest from its fit and jackknives.
ValidateData validateDataOf(const FitAnalysis& a);

// validate_data.json, and its reader (bounds and consistency checked; one-line gtbake::Error
// naming `where` otherwise).
nlohmann::ordered_json validateDataJson(const ValidateData& data);
// The file's text: the header keys indented, each view on one compact line.
std::string validateDataText(const ValidateData& data);
ValidateData parseValidateData(const nlohmann::json& j, const std::string& where);
// Reads DIR/validate_data.json of a fit output set, verified against DIR/fit.manifest.json.
ValidateData readValidateData(const std::filesystem::path& dir);

// The views grouped by `field` (&ViewSums::scene or &ViewSums::type): the groups in order of
// first appearance and each view's group, as the jackknives group them (groupByScene).
Grouping groupViews(const std::vector<ViewSums>& views, std::string ViewSums::*field);

// Σ over a view's points in bins [first, last) and albedo j of (p(A) − q(A))² for two cubics,
// and of (G − p(A))²: the exact sums above.
double sumSquaredDifference(const ViewSums& v, std::size_t first, std::size_t last, const Cubic& p,
                            const Cubic& q);
double sumSquaredError(const ViewSums& v, std::size_t first, std::size_t last, std::size_t albedo,
                       const Cubic& p);
double pointCount(const ViewSums& v, std::size_t first, std::size_t last);

}  // namespace gtbake
