// Scene-level uncertainty of validate-gtso's error figures: delete-one-group jackknives of each
// method's RMSE against the path-traced S, with the views grouped by scene (the cluster) or by
// scene type (docs/validate_gtso.md; the same estimator as the fit's, docs/fit.md §5).
//
// For G groups and a statistic θ computed from the per-view sums, θ_(g) is θ without group g's
// views and SE = √((G − 1)/G Σ_g (θ_(g) − θ̄)²). The RMSE is a smooth function of the sums
// (Σ e², count), so each replicate costs a subtraction.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "validate_gtso/specular_methods.h"
#include "validate_gtso/specular_sweep.h"

namespace gtbake {

// Per method (`names`, same order as `cells`) the RMSE over every view and roughness, its
// jackknife SE and the group count n, grouped by `unit` ("scene" or "type"); cells[m][view][r].
// Fewer than 3 groups: {"available": false, ...}.
nlohmann::ordered_json methodJackknifeJson(
    const SpecularSweep& sweep, const std::string& unit, const std::vector<std::string>& names,
    const std::vector<std::vector<std::vector<ErrorStats>>>& cells);

}  // namespace gtbake
