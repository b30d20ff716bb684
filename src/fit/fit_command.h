// `gtbake fit` and `gtbake validate`: Equation 10 from a sweep (SPEC §1.3, §2).
#pragma once

#include <array>
#include <filesystem>
#include <optional>

namespace gtbake {

// {a1, a0, b1, b0, c1, c0}: a(ρ) = a1·ρ + a0 etc., G = a·A³ − b·A² + c·A.
using MultiBounceCoeffs = std::array<double, 6>;
inline constexpr MultiBounceCoeffs kPaperCoeffs = {2.0404,  -0.3324, 4.7951,
                                                   -0.6417, 2.7552,  0.6903};

struct FitOptions {
  std::filesystem::path sweep;                  // directory written by `gtbake sweep`
  std::filesystem::path out;                    // fit.json
  std::optional<std::filesystem::path> report;  // HTML report directory (default: beside `out`)
  MultiBounceCoeffs shipped = kPaperCoeffs;     // the constants compared against the refit
  bool eiv_correction = true;  // report the split-half jackknife correction (docs/fit.md §4)
  bool progress = true;
};

struct FitResult {
  MultiBounceCoeffs linear{};
  MultiBounceCoeffs linear_se{};
};

// Writes fit.json and the report; prints the summary table to stdout.
FitResult runFit(const FitOptions& options);

struct ValidateOptions {
  std::filesystem::path sweep;
  MultiBounceCoeffs coeffs = kPaperCoeffs;
  bool progress = true;
};

// Prints the error table of `coeffs` beside the refit's. Writes nothing.
void runValidate(const ValidateOptions& options);

}  // namespace gtbake
