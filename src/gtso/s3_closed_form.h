// The closed-form approximation of S3 for engines short of samplers (docs/gtso.md §7): the form is
// gtsoS3ClosedForm in runtime/gtso_runtime.h (a log-logistic step in the odds of A whose
// median and slopes are polynomials in cos theta_o and r_p); this file makes its point sets,
// fits its kGtsoS3ClosedFormCoeffs coefficients with Ceres and measures it.
//
// Objective: least squares, (1/2) sum_i (S_form(A_i, cos theta_o_i, r_p_i; k) - S3_i)^2 over
// the training points, S3_i exact (the integrator). One Ceres residual block per lobe (its points
// share cos theta_o and r_p): the lobe's median and slopes and their derivatives in k are taken
// once per lobe with Ceres Jets, the per-point part by the chain rule. Single-threaded Ceres and
// counter-based point sets: the same bytes on any thread count.
//
// Point sets (all deterministic in their seed): training and validation sets from
// makeClosedFormPoints (dense near the mirror step and at grazing and normal views, plus uniform
// A); the test sets are gtso's end-to-end 3D point sets (makeErrorPoints, seeds 1..n, uniform and
// stress), fresh for the fit.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <vector>

#include "gtso/gtso_tables.h"
#include "runtime/gtso_runtime.h"

namespace gtbake::gtso {

using S3ClosedFormCoeffs = std::array<double, kGtsoS3ClosedFormCoeffs>;

// Lobes by kind (l mod 4): uniform cos theta_o, grazing (cos theta_o in [0, 0.1]), near normal
// (cos theta_o in [0.9, 1]), uniform; r_p uniform in [0, 1]. Per lobe, perLobe cones: even ones
// A uniform, odd ones alpha_v uniform within 6 alpha + 0.02 rad of the step alpha_v = theta_o.
ErrorPoints makeClosedFormPoints(int lobes, int perLobe, std::uint64_t seed, int cells);

struct S3ClosedFormFit {
  S3ClosedFormCoeffs k{};
  double objective = 0.0;  // (1/2) sum of squared residuals at k (training set)
  double initial_objective = 0.0;
  double rms = 0.0;  // sqrt(2 objective / points)
  int points = 0, iterations = 0;
  bool converged = false;
  // Flatness: standard errors sqrt(diag((J^T J)^-1) * 2 objective / (points - coefficients)),
  // empty if J^T J is rank deficient (reciprocal condition < 1e-14); and the objective at the
  // float-rounded k.
  std::vector<double> standard_errors;
  double objective_float_k = 0.0;
};

// Fits k on `train` (points in groups of perLobe sharing a lobe) from `start`. Throws
// gtbake::Error if Ceres fails.
S3ClosedFormFit fitS3ClosedForm(const ErrorPoints& train, int perLobe,
                                const S3ClosedFormCoeffs& start);
// The starting point: every polynomial 0 (a = b = alpha^2, slopes 1 + sin(2 theta_o)/(2 alpha)).
S3ClosedFormCoeffs closedFormStart();
// The coefficients of a cold fit from closedFormStart() on the default training set
// (bench_s3_closed_form): the start `gtbake gtso` uses, a few iterations from its optimum.
S3ClosedFormCoeffs closedFormWarmStart();

// Error of the shipped function (float coefficients, float arithmetic: the generated header's
// code) against exact S, split at r_p = 0.1.
struct ClosedFormBand {
  ErrorStats stats;
  int count = 0;
};
struct ClosedFormErrors {
  ClosedFormBand rough, smooth;  // r_p >= 0.1, r_p < 0.1
};
ClosedFormErrors closedFormErrors(const S3ClosedFormCoeffs& k, const ErrorPoints& pts);
// Accumulates another point set into e.
void addClosedFormErrors(const S3ClosedFormCoeffs& k, const ErrorPoints& pts, ClosedFormErrors& e);
void finishClosedFormErrors(ClosedFormErrors& e);  // sums of squares -> RMS

// The shipped (float) function at one point.
float closedFormAt(const S3ClosedFormCoeffs& k, const GtsoPoint& p);

// The stage `gtbake gtso` runs: training and validation sets (kClosedFormTrainSeed,
// kClosedFormValidationSeed), the fit from closedFormWarmStart(), and the errors of the shipped
// float function on the validation set and on `tests` (gtso's end-to-end 3D point sets, seeds
// test_seeds). Returns gtso.json's "closed_form" object and the coefficients.
// train_lobes training lobes of kConesPerLobe points each (the shipped fit: 2,048) and a quarter as
// many validation lobes. Fewer lobes fit faster and worse (tests of the stage's plumbing use 64).
inline constexpr int kClosedFormTrainLobes = 2048;
inline constexpr std::uint64_t kClosedFormTrainSeed = 1000;
inline constexpr std::uint64_t kClosedFormValidationSeed = 2000;
struct ClosedFormStage {
  nlohmann::json json;
  S3ClosedFormCoeffs k{};
};
ClosedFormStage runClosedFormStage(const std::vector<const ErrorPoints*>& tests,
                                   const std::vector<std::uint64_t>& test_seeds, int cells,
                                   int train_lobes = kClosedFormTrainLobes);

}  // namespace gtbake::gtso
