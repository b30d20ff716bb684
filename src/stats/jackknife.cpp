#include "stats/jackknife.h"

#include <cmath>

namespace gtbake {

namespace {

// Two-sided 95 % quantiles t_{0.975, ν} of Student's t for ν = 1..30 (standard tables).
// clang-format off
constexpr double kT975[30] = {
    12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
     2.201, 2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
     2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
// clang-format on

}  // namespace

double jackknifeSe(const std::vector<double>& replicates) {
  const double S = static_cast<double>(replicates.size());
  double mean = 0.0;
  for (double z : replicates) mean += z / S;
  double ss = 0.0;
  for (double z : replicates) ss += (z - mean) * (z - mean);
  return std::sqrt((S - 1.0) / S * ss);
}

double studentT975(std::size_t dof) {
  if (dof >= 1 && dof <= 30) return kT975[dof - 1];
  // Beyond the table, the Cornish-Fisher expansion of the t quantile in 1/ν about the normal's
  // z = 1.959964 (Abramowitz & Stegun 26.7.5, four terms): its error at ν = 31 is below 1e-6, far
  // under the table's three decimals, and it tends to z as ν grows.
  constexpr double z = 1.959963984540054;
  const double nu = static_cast<double>(dof);
  const double z2 = z * z;
  const double g1 = (z2 + 1.0) * z / 4.0;
  const double g2 = ((5.0 * z2 + 16.0) * z2 + 3.0) * z / 96.0;
  const double g3 = (((3.0 * z2 + 19.0) * z2 + 17.0) * z2 - 15.0) * z / 384.0;
  const double g4 =
      ((((79.0 * z2 + 776.0) * z2 + 1482.0) * z2 - 1920.0) * z2 - 945.0) * z / 92160.0;
  return z + (((g4 / nu + g3) / nu + g2) / nu + g1) / nu;
}

}  // namespace gtbake
