// The HTML report of a fit: one self-contained index.html plus SVG figures, all drawn by the
// small SVG plotter in fit_report.cpp (no dependencies, crisp at any zoom).
//
// Figures: (1) the paper's Figure 6: A vs G per scene, every albedo, with the per-albedo cubics;
// (2) Figure 7: the per-albedo cubics (left) and a(ρ), b(ρ), c(ρ) with ±2 SE bars and their lines;
// (3) Eq. 10 refit against the shipped constants, G(A) per albedo; plus the error tables.
// Scatter points are subsampled deterministically (a fixed stride per scene).
#pragma once

#include <filesystem>

#include "fit/fit_errors.h"
#include "fit/multibounce_fit.h"
#include "fit/scene_mix.h"

namespace gtbake {

struct FitReportInput {
  const SweepData* data = nullptr;
  const MultiBounceFit* fit = nullptr;
  MultiBounceCoeffs shipped{};
  const ErrorTable* refit_errors = nullptr;
  const ErrorTable* shipped_errors = nullptr;
  CurveDifference curve_difference;
  const std::vector<SceneMixRow>* scene_mix = nullptr;  // leave-one-scene-out refits
};

// Writes dir/index.html and dir/*.svg (each atomically); creates dir.
void writeFitReport(const std::filesystem::path& dir, const FitReportInput& input);

}  // namespace gtbake
