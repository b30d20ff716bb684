#include "fit/fit_analysis.h"

#include <algorithm>
#include <cmath>

namespace gtbake {

namespace {

// The per-scene statistics of `weighting`, reusing the fit's where they are the same sums: scene
// weights are constant within a scene, so scene-weighted sums are pixel sums times a constant.
std::vector<LevelStatistics> statisticsFor(const SweepData& data, const MultiBounceFit& fit,
                                           Weighting weighting) {
  if (weighting == fit.settings.weighting) return fit.scene_stats;
  if (weighting == Weighting::kView && fit.settings.weighting == Weighting::kPixel) {
    const std::vector<double> w = pointWeights(data, Weighting::kView);
    std::vector<LevelStatistics> out(fit.scene_stats.size());
    for (std::size_t s = 0; s < out.size(); ++s) {
      for (int l = 0; l < kLevels; ++l) {
        out[s][l] = fit.scene_stats[s][l].scaled(w[data.scenes[s].begin]);
      }
    }
    return out;
  }
  return sceneStatistics(data, pointWeights(data, weighting));
}

LevelStatistics total(const std::vector<LevelStatistics>& scenes) {
  return sumScenes(scenes, std::vector<bool>(scenes.size(), true));
}

}  // namespace

OpenSurface openSurface(const MultiBounceCoeffs& k) {
  OpenSurface out;
  out.slope = k[0] - k[2] + k[4];
  out.intercept = k[1] - k[3] + k[5];
  for (double rho : {kRhoMin, kRhoMax}) {
    out.max_deviation =
        std::max(out.max_deviation, std::abs(out.intercept + out.slope * rho - 1.0));
  }
  return out;
}

std::vector<ViewWeight> viewWeights(const SweepData& data, const std::vector<double>& weights) {
  double sum = 0.0;
  for (double w : weights) sum += w;
  std::vector<ViewWeight> out;
  for (const SweepScene& s : data.scenes) {
    double part = 0.0;
    for (std::size_t i = s.begin; i < s.end; ++i) part += weights[i];
    out.push_back({s.name, s.end - s.begin, part / sum});
  }
  return out;
}

std::vector<Alternative> weightingAlternatives(const SweepData& data, const MultiBounceFit& fit) {
  std::vector<Alternative> out;
  for (Weighting w : kWeightings) {
    FitSettings settings = fit.settings;
    settings.weighting = w;
    const MultiBounceCoeffs k = w == fit.settings.weighting
                                    ? fit.linear.coeffs
                                    : coefficientsFromStatistics(total(statisticsFor(data, fit, w)),
                                                                 data.albedos, settings);
    out.push_back({weightingName(w), k, {}, errorTable(data, k).rmse});
  }
  for (Alternative& a : out) a.vs_default = maxCurveDifference(a.linear, out.front().linear);
  return out;
}

Alternative constraintAlternative(const SweepData& data, const MultiBounceFit& fit) {
  FitSettings settings = fit.settings;
  // A shape-constrained fit against the fit without any constraint; otherwise the other
  // constrain-open setting.
  settings.constrain_open = !settings.constrain_open && !settings.shape_constrained;
  settings.shape_constrained = false;
  const MultiBounceCoeffs k =
      coefficientsFromStatistics(total(fit.scene_stats), data.albedos, settings);
  const std::string name = fit.settings.shape_constrained ? "shape-constrained off"
                           : settings.constrain_open      ? "constrain-open on"
                                                          : "constrain-open off";
  return {name, k, maxCurveDifference(k, fit.linear.coeffs), errorTable(data, k).rmse};
}

double constraintCost(const FitAnalysis& a) {
  const FitSettings& s = a.fit.settings;
  return s.constrain_open || s.shape_constrained ? a.refit_errors.rmse - a.constraint.rmse
                                                 : a.constraint.rmse - a.refit_errors.rmse;
}

const char* constraintName(const FitSettings& settings) {
  return settings.shape_constrained ? "the shape constraints (G(1, rho) = 1, dG/dA >= 0, G >= 0)"
                                    : "a - b + c = 1 (--constrain-open)";
}

ProfileChecks profileChecks(const FitAnalysis& a) {
  ProfileChecks p;
  p.shape = shapeChecks(a.fit.linear.coeffs);
  p.cubic_rmse = a.refit_errors.rmse;
  p.floor_rmse = a.floor.rmse;
  p.ratio = p.cubic_rmse / p.floor_rmse;
  p.adequate = p.ratio <= kAdequacyRatio;
  p.table = tableFit(a.data);
  p.gate = a.held_out_errors ? profileGate(p.shape, a.held_out_errors->rmse, a.shipped_errors.rmse)
                             : ProfileGate{false, "no held-out RMSE (fewer than two scenes)"};
  return p;
}

std::optional<ErrorTable> heldOutErrors(const SweepData& data, const SceneJackknife& by_scene) {
  const Grouping groups = groupByScene(data);
  if (by_scene.leave_one_out.size() != groups.names.size()) return std::nullopt;
  std::vector<MultiBounceCoeffs> per_view;
  for (std::size_t v = 0; v < data.scenes.size(); ++v) {
    per_view.push_back(by_scene.leave_one_out[groups.of[v]].linear);
  }
  return errorTable(data, per_view);
}

FitAnalysis analyzeSweep(const std::filesystem::path& sweep, const FitSettings& settings,
                         const MultiBounceCoeffs& shipped, Progress* progress, const AoInput& input,
                         const LoadedSweeps* loaded) {
  // A screen-space estimator is scored against the truth within its own radius (docs/sweep.md,
  // "Near-field truth") unless --truth unbounded; ray-traced A keeps the unbounded G.
  const std::optional<double> radius = truthRadius(input);
  SweepData data = loadSweep(sweep, radius, loaded);
  useScreenEstimate(&data, input);
  if (progress != nullptr) progress->add(1);
  // Â is a deterministic function of the G-buffer: no noise in the regressor, nothing for the
  // errors-in-variables correction to remove (its estimate would be G's noise alone).
  FitSettings used = settings;
  used.eiv_correction = settings.eiv_correction && input.rayTraced();
  // A profile ships to engines: fitted under the shape it must have (docs/profiles.md §7).
  used.shape_constrained = settings.shape_constrained || !input.rayTraced();
  FitAnalysis a = analyzePoints(std::move(data), used, shipped, {}, progress);
  a.input = input;
  a.truth_radius = radius;
  if (radius) {
    // The same views and pixels with the unbounded G; the Â already read serves both.
    SweepData unbounded = loadSweep(sweep, std::nullopt, loaded);
    unbounded.full.A = a.data.full.A;
    a.unbounded = UnboundedComparison{errorTable(unbounded, shipped).rmse,
                                      errorTable(unbounded, a.fit.linear.coeffs).rmse};
  }
  return a;
}

FitAnalysis analyzePoints(SweepData data, const FitSettings& settings,
                          const MultiBounceCoeffs& shipped, const BandRule& rule,
                          Progress* progress) {
  const auto step = [&] {
    if (progress != nullptr) progress->add(1);
  };
  FitAnalysis a;
  a.data = std::move(data);
  a.fit = fitMultiBounce(a.data, settings);
  a.view_weights = viewWeights(a.data, a.fit.weights);
  step();
  a.jackknife = sceneJackknife(a.data, a.fit, shipped, rule);
  a.type_jackknife = typeJackknife(a.data, a.fit, shipped, rule);
  step();
  a.refit_errors = errorTable(a.data, a.fit.linear.coeffs);
  a.held_out_errors = heldOutErrors(a.data, a.jackknife);
  a.shipped_errors = errorTable(a.data, shipped);
  a.shipped_difference = maxCurveDifference(a.fit.linear.coeffs, shipped);
  a.shipped_score = scoreAgainstBand(a.jackknife, a.fit.linear.coeffs, shipped);
  a.open_surface = openSurface(a.fit.linear.coeffs);
  step();
  a.weightings = weightingAlternatives(a.data, a.fit);
  step();
  a.constraint = constraintAlternative(a.data, a.fit);
  step();
  a.floor = fitFloor(a.data);
  if (settings.shape_constrained) a.profile = profileChecks(a);
  step();
  return a;
}

}  // namespace gtbake
