// validate's data and verdict (docs/fit.md §5, §10): the binned sums give the point-by-point
// errors exactly, the file reads back to the same report, hostile files are one-line errors, and
// the verdict by range of A finds a known error in its range, says "too few scenes" without
// power, and honours a tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/error.h"
#include "fit/fit_analysis.h"
#include "fit/validate_output.h"
#include "fit/validate_report.h"
#include "synthetic_sweep.h"

namespace gtbake {
namespace {

using nlohmann::json;

// Scenes around kPaperCoeffs that differ in c (level) and in a, b together (shape).
SweepData sceneMix(std::size_t scenes, double tau, std::size_t points, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<test::SyntheticScene> mix;
  for (std::size_t s = 0; s < scenes; ++s) {
    MultiBounceCoeffs k = kPaperCoeffs;
    const double level = tau * normal(rng), shape = tau * normal(rng);
    k[5] += level;
    k[0] += shape;
    k[2] += shape;
    mix.push_back({"s" + std::to_string(s), k, points});
  }
  SweepData data = test::pooledSweep(mix, 0.004, 0.004, 0.2, seed * 7);
  for (std::size_t v = 0; v < data.scenes.size(); ++v) {
    data.scenes[v].type = "t" + std::to_string(v % 4);
  }
  return data;
}

// The analysis validate reads, from in-memory points (a coarse band grid keeps it fast).
FitAnalysis analysis(SweepData data) {
  return analyzePoints(std::move(data), {}, kPaperCoeffs, {50, 16, {0.95, 2000, 3}});
}

// The refit plus an error k·A(1 − A) at every ρ (b0 and c0 up by k): 0 at A = 0 and A = 1, the
// largest, k/4, at A = 0.5.
MultiBounceCoeffs withMidError(const MultiBounceCoeffs& refit, double peak) {
  MultiBounceCoeffs k = refit;
  k[3] += 4.0 * peak;
  k[5] += 4.0 * peak;
  return k;
}

double relative(double a, double b) {
  return std::abs(a - b) / std::max(std::abs(b), 1e-300);
}

TEST(ValidateData, BinnedSumsGiveThePointErrorsExactly) {
  const FitAnalysis a = analysis(sceneMix(8, 0.03, 3000, 21));
  const ValidateData d = validateDataOf(a);
  const MultiBounceCoeffs given = withMidError(a.fit.linear.coeffs, 0.01);
  const ValidateReport r = validateReport(d, given);
  const ErrorTable direct = errorTable(a.data, given);
  const ErrorTable refit = errorTable(a.data, a.fit.linear.coeffs);
  const ErrorTable held = *heldOutErrors(a.data, a.jackknife);
  // Expanded squares cancel ~2 digits (RMSE 0.02 against G ~ 0.5): 1e-10 is a thousand times
  // the rounding measured (1e-13).
  EXPECT_LT(relative(r.all.given, direct.rmse), 1e-10);
  EXPECT_LT(relative(r.all.refit, refit.rmse), 1e-10);
  EXPECT_LT(relative(r.all.held_out, held.rmse), 1e-10);
  for (std::size_t j = 0; j < direct.per_albedo.size(); ++j) {
    EXPECT_LT(relative(r.per_albedo[j].given, direct.per_albedo[j].rmse), 1e-10) << j;
  }
  for (std::size_t v = 0; v < direct.per_scene.size(); ++v) {
    EXPECT_LT(relative(r.per_view[v].given, direct.per_scene[v].rmse), 1e-10) << v;
  }
  // The pixel-weighted RMS difference, point by point.
  double sum = 0.0;
  for (double A : a.data.full.A) {
    for (double rho : a.data.albedos) {
      const double diff =
          evalMultiBounce(given, A, rho) - evalMultiBounce(a.fit.linear.coeffs, A, rho);
      sum += diff * diff;
    }
  }
  const double rms = std::sqrt(sum / (a.data.points() * a.data.albedos.size()));
  EXPECT_LT(relative(r.rms_difference.rms, rms), 1e-10);
  EXPECT_TRUE(r.rms_difference.interval);
  EXPECT_LE(r.rms_difference.lo, r.rms_difference.rms);
  EXPECT_GE(r.rms_difference.hi, r.rms_difference.rms);
}

TEST(ValidateData, FileReadsBackToTheSameReport) {
  const FitAnalysis a = analysis(sceneMix(6, 0.03, 1500, 22));
  const ValidateData d = validateDataOf(a);
  const ValidateData back = parseValidateData(json::parse(validateDataText(d)), "test");
  const MultiBounceCoeffs given = withMidError(a.fit.linear.coeffs, 0.02);
  json one = json::parse(validateReportJson(d, validateReport(d, given)).dump());
  json two = json::parse(validateReportJson(back, validateReport(back, given)).dump());
  one.erase("data");
  two.erase("data");
  EXPECT_EQ(one, two);
}

// Each mutation of a valid file is refused with a gtbake::Error (never a crash or a report).
TEST(ValidateData, HostileFilesAreOneLineErrors) {
  const FitAnalysis a = analysis(sceneMix(4, 0.03, 1200, 23));
  const json good = json::parse(validateDataText(validateDataOf(a)));
  const std::vector<std::function<void(json&)>> mutations = {
      [](json& j) { j["format"] = "something else"; },
      [](json& j) { j["views"][1]["name"] = j["views"][0]["name"]; },
      [](json& j) { j["views"][0]["bins"][0]["bin"] = 20; },
      [](json& j) { j["views"][0]["bins"][1]["bin"] = j["views"][0]["bins"][0]["bin"]; },
      [](json& j) { j["views"][0]["bins"][0]["power"][0] = -3.0; },
      [](json& j) { j["views"][0]["bins"][0]["power"][2] = "x"; },
      [](json& j) { j["views"][0]["bins"][0]["albedo"].erase(0); },
      [](json& j) { j["scene_jackknife"]["replicas"][0]["left_out"] = "elsewhere"; },
      [](json& j) { j["scene_jackknife"]["range_thresholds"].erase(0); },
      [](json& j) {
        j["band_rule"]["ranges"] = json::array({0.0, 0.33, 1.0});
      },
      [](json& j) { j["band_rule"]["a_steps"] = 100000; },
      [](json& j) { j["sweep"]["albedos"][0] = 1.5; },
      [](json& j) { j["settings"]["weighting"] = "uniform"; },
      [](json& j) { j.erase("refit"); },
      [](json& j) { j["views"] = json::array(); },
  };
  EXPECT_NO_THROW(parseValidateData(good, "good"));
  for (std::size_t m = 0; m < mutations.size(); ++m) {
    json bad = good;
    mutations[m](bad);
    EXPECT_THROW(parseValidateData(bad, "bad"), Error) << "mutation " << m;
  }
}

TEST(CurveVerdict, KnownMidRangeErrorIsFoundInItsRange) {
  const FitAnalysis a = analysis(sceneMix(40, 0.01, 1500, 24));
  const ValidateData d = validateDataOf(a);
  const CurveVerdict same = validateReport(d, a.fit.linear.coeffs).verdict;
  ASSERT_EQ(same.verdict, Verdict::kConsistent) << same.headline;
  for (const RangeScore& r : same.ranges) ASSERT_LT(r.detectable.value, 0.02) << r.text;
  for (double peak : {0.02, 0.03}) {
    const CurveVerdict v = validateReport(d, withMidError(a.fit.linear.coeffs, peak)).verdict;
    EXPECT_EQ(v.verdict, Verdict::kOutside) << v.headline;
    EXPECT_EQ(v.ranges[1].verdict, Verdict::kOutside) << v.ranges[1].text;
    EXPECT_NEAR(v.ranges[1].max_difference.value, peak, 1e-12);
    EXPECT_NEAR(v.ranges[1].max_difference.A, 0.5, 1e-12);
  }
}

TEST(CurveVerdict, ToleranceDecidesWhetherAnOutsideRangeFails) {
  const FitAnalysis a = analysis(sceneMix(40, 0.01, 1500, 25));
  const ValidateData d = validateDataOf(a);
  const MultiBounceCoeffs given = withMidError(a.fit.linear.coeffs, 0.03);
  VerdictRule loose;
  loose.fail_above = 0.04;
  const CurveVerdict within = validateReport(d, given, loose).verdict;
  EXPECT_EQ(within.ranges[1].verdict, Verdict::kOutside);
  EXPECT_FALSE(within.ranges[1].fails);
  EXPECT_EQ(within.verdict, Verdict::kConsistent) << within.headline;
  VerdictRule tight;
  tight.fail_above = 0.025;
  EXPECT_EQ(validateReport(d, given, tight).verdict.verdict, Verdict::kOutside);
}

TEST(CurveVerdict, ThreeScenesAreTooFewToJudge) {
  const FitAnalysis three = analysis(sceneMix(3, 0.05, 2000, 26));
  const CurveVerdict v = validateReport(validateDataOf(three), kPaperCoeffs).verdict;
  ASSERT_TRUE(v.available);
  EXPECT_EQ(v.verdict, Verdict::kTooFewScenes) << v.headline;
  const FitAnalysis two = analysis(sceneMix(2, 0.05, 2000, 27));
  const CurveVerdict none = validateReport(validateDataOf(two), kPaperCoeffs).verdict;
  EXPECT_FALSE(none.available);
  EXPECT_EQ(none.verdict, Verdict::kTooFewScenes);
}

}  // namespace
}  // namespace gtbake
