// Generic delete-one-group jackknife helpers shared by every stage that reports a scene-level
// uncertainty (fit, validate-gtso, tune): the SE of a scalar from its replicates and the t
// quantile of its interval (docs/fit.md §5).
#pragma once

#include <cstddef>
#include <vector>

namespace gtbake {

// Fewer scenes than this make a scene-level uncertainty meaningless (scenes; with 2 the
// "variance" has one degree of freedom and the t quantile is 12.7).
inline constexpr std::size_t kMinJackknifeScenes = 3;

// The delete-one jackknife SE of a scalar from its S replicates z_(s):
// √((S − 1)/S · Σ (z_(s) − z̄)²) (docs/fit.md §5; S ≥ 1).
double jackknifeSe(const std::vector<double>& replicates);

// Two-sided 95 % quantile of Student's t with `dof` degrees of freedom (dof ≥ 1): a table to 30,
// then the Cornish-Fisher expansion (2.0117 at the default corpus's 47; 1.96 only in the limit).
double studentT975(std::size_t dof);

}  // namespace gtbake
