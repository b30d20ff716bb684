// The HTML report of a fit: one self-contained index.html plus SVG figures (svg_plot.h).
//
// Leads with the curve band and the verdict on the shipped constants, then: (1) the band per
// albedo: G_shipped − G_refit against ±t·SE_G (one panel per albedo) and G(A) with the band;
// (2) the paper's Figure 7: per-albedo cubics and a(ρ), b(ρ), c(ρ) with the jackknife band of
// each line and ±2 SE (Monte Carlo) bars; (3) the paper's Figure 6: A vs G per scene; plus the
// tables (coefficients, correlation, weightings, floor and errors, scene weights, leave one out).
// Scatter points are subsampled deterministically (a fixed stride per scene).
#pragma once

#include <filesystem>
#include <string>

#include "fit/curve_verdict.h"
#include "fit/fit_analysis.h"

namespace gtbake {

class OutputSet;

// Stages index.html, the *.svg figures and the views' thumbnails (views/*.png) in `set` under
// `prefix` ("" or "report/"), so the report is committed with (and verified like) the rest of the
// set and links nothing outside its folder. With `verdict`, the page leads with the shipped
// constants' verdict by range of A (docs/fit.md §5).
void writeFitReport(OutputSet& set, const std::string& prefix, const FitAnalysis& a,
                    const MultiBounceCoeffs& shipped, const CurveVerdict* verdict = nullptr);

}  // namespace gtbake
