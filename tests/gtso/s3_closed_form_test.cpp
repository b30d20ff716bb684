// The closed-form S3 (gtsoS3ClosedForm, src/gtso/s3_closed_form.h): the fit recovers known
// coefficients from data the form itself generates, it is deterministic across thread counts, the
// form keeps its exact limits and monotonicity, and the shipped float function meets the error
// the stage reports in gtso.json on fresh points against the integrator.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/rng.h"
#include "common/threads.h"
#include "gtso/gtso_integrator.h"
#include "gtso/s3_closed_form.h"
#include "runtime/gtso_runtime.h"

namespace gtbake::gtso {
namespace {

constexpr int kPerLobe = 32;

// Points in lobes of kPerLobe, S = the form at k (double), A uniform and near the step.
ErrorPoints syntheticPoints(const S3ClosedFormCoeffs& k, int lobes, std::uint64_t seed) {
  const CounterRng rng(seed, 5);
  ErrorPoints out;
  for (int l = 0; l < lobes; ++l) {
    const auto u = rng.uniform4(l, 0);
    const double rp = 0.05 + 0.95 * u[0], theta_o = std::acos(u[1]);
    for (int j = 0; j < kPerLobe; ++j) {
      const auto v = rng.uniform4(l, 1 + j);
      double A = v[0];
      if (j % 2 == 1) {
        const double s = std::sin(std::clamp(theta_o + (6.0 * rp * rp + 0.02) * (2.0 * v[1] - 1.0),
                                             0.0, 1.5707963267948966));
        A = s * s;
      }
      out.points.push_back({A, theta_o, rp, theta_o});
      out.exact.push_back(gtsoS3ClosedForm(k.data(), A, std::cos(theta_o), rp));
    }
  }
  return out;
}

TEST(S3ClosedForm, FitRecoversKnownCoefficients) {
  const S3ClosedFormCoeffs truth = closedFormWarmStart();
  const ErrorPoints data = syntheticPoints(truth, 512, 17);
  // Start away from the truth: every coefficient moved by 5% of its size plus 0.05.
  S3ClosedFormCoeffs start = truth;
  const CounterRng rng(23, 0);
  for (int i = 0; i < kGtsoS3ClosedFormCoeffs; ++i) {
    const double r = 2.0 * rng.uniform4(i, 0)[0] - 1.0;
    start[i] += r * (0.05 * std::abs(truth[i]) + 0.05);
  }
  const S3ClosedFormFit fit = fitS3ClosedForm(data, kPerLobe, start);
  EXPECT_GT(fit.initial_objective, 1.0);
  EXPECT_LT(fit.objective, 1e-12) << "the form's own data must be fitted exactly";
  // The function is recovered everywhere (fresh points) ...
  const ErrorPoints fresh = syntheticPoints(truth, 128, 99);
  for (std::size_t i = 0; i < fresh.points.size(); ++i) {
    const GtsoPoint& p = fresh.points[i];
    ASSERT_NEAR(gtsoS3ClosedForm(fit.k.data(), p.A, std::cos(p.theta_o), p.r_p), fresh.exact[i],
                1e-6);
  }
  // ... and so are the coefficients, within a small multiple of their standard errors' scale
  // (noise-free data: the optimum is the truth).
  for (int i = 0; i < kGtsoS3ClosedFormCoeffs; ++i) {
    EXPECT_NEAR(fit.k[i], truth[i], 1e-3 * (1.0 + std::abs(truth[i]))) << "coefficient " << i;
  }
}

TEST(S3ClosedForm, SameCoefficientsOnOneAndTwoThreads) {
  auto run = [](int threads) {
    const ThreadLimit limit(threads);
    const ErrorPoints train = makeClosedFormPoints(128, kPerLobe, 5, 24);
    return fitS3ClosedForm(train, kPerLobe, closedFormWarmStart());
  };
  const S3ClosedFormFit a = run(1), b = run(2);
  for (int i = 0; i < kGtsoS3ClosedFormCoeffs; ++i) EXPECT_EQ(a.k[i], b.k[i]) << i;
  EXPECT_EQ(a.objective, b.objective);
}

TEST(S3ClosedForm, ExactLimitsAndMonotoneInA) {
  float k[kGtsoS3ClosedFormCoeffs];
  const S3ClosedFormCoeffs kd = closedFormWarmStart();
  for (int i = 0; i < kGtsoS3ClosedFormCoeffs; ++i) k[i] = static_cast<float>(kd[i]);
  const CounterRng rng(8, 0);
  for (int l = 0; l < 500; ++l) {
    const auto u = rng.uniform4(l, 0);
    const float cb = u[0], rp = l % 10 == 0 ? 0.0f : u[1];
    EXPECT_EQ(gtsoS3ClosedForm(k, 0.0f, cb, rp), 0.0f);
    EXPECT_EQ(gtsoS3ClosedForm(k, 1.0f, cb, rp), 1.0f);
    float prev = 0.0f;
    for (int i = 1; i < 400; ++i) {
      const float s = gtsoS3ClosedForm(k, i / 400.0f, cb, rp);
      ASSERT_TRUE(s >= prev - 1e-6f && s <= 1.0f) << "A " << i / 400.0f << " cos " << cb;
      prev = s;
    }
  }
}

// Fresh points (seeds the stage never saw): |shipped float function - integrator| stays within
// what closed_form.test reports (max within 0.01, RMS within 25%).
void expectMeetsReported(const nlohmann::json& cf, std::uint64_t firstSeed) {
  float k[kGtsoS3ClosedFormCoeffs];
  ASSERT_EQ(cf.at("coefficients").size(), static_cast<std::size_t>(kGtsoS3ClosedFormCoeffs));
  for (int i = 0; i < kGtsoS3ClosedFormCoeffs; ++i) k[i] = cf["coefficients"][i].get<float>();
  double max = 0.0, sum = 0.0;
  int n = 0;
  for (std::uint64_t seed = firstSeed; seed < firstSeed + 2; ++seed) {
    for (PointSet set : {PointSet::kUniform, PointSet::kStress}) {
      const ErrorPoints pts = makeErrorPoints(3, set, 512, 16, seed, kDefaultLobeCells);
      for (std::size_t i = 0; i < pts.points.size(); ++i) {
        const GtsoPoint& p = pts.points[i];
        if (p.r_p < 0.1) continue;
        const float s =
            gtsoS3ClosedForm(k, static_cast<float>(p.A), static_cast<float>(std::cos(p.theta_o)),
                             static_cast<float>(p.r_p));
        const double d = std::abs(s - pts.exact[i]);
        max = std::max(max, d);
        sum += d * d;
        ++n;
      }
    }
  }
  const double rms = std::sqrt(sum / n);
  const nlohmann::json& rep = cf["test"]["errors"]["r_p_ge_0.1"];
  std::printf(
      "closed form on %d fresh points, r_p >= 0.1: max %.4f rms %.5f (reported %.4f %.5f)\n", n,
      max, rms, rep["max"].get<double>(), rep["rms"].get<double>());
  EXPECT_LE(max, rep["max"].get<double>() + 0.01);
  EXPECT_LE(rms, 1.25 * rep["rms"].get<double>());
}

TEST(S3ClosedForm, StageMeetsItsReportedErrorOnFreshPoints) {
  std::vector<ErrorPoints> tests;
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    tests.push_back(makeErrorPoints(3, PointSet::kUniform, 256, 16, seed, kDefaultLobeCells));
    tests.push_back(makeErrorPoints(3, PointSet::kStress, 64, 16, seed, kDefaultLobeCells));
  }
  std::vector<const ErrorPoints*> ptrs;
  for (const ErrorPoints& t : tests) ptrs.push_back(&t);
  const ClosedFormStage stage = runClosedFormStage(ptrs, {1, 2}, kDefaultLobeCells);
  const nlohmann::json& cf = stage.json;
  EXPECT_TRUE(cf["objective"]["converged"].get<bool>());
  EXPECT_EQ(cf["flatness"]["standard_errors"].size(),
            static_cast<std::size_t>(kGtsoS3ClosedFormCoeffs));
  // The shipped coefficients are the fit's, and the function reads them as the header does.
  for (int i = 0; i < kGtsoS3ClosedFormCoeffs; ++i) {
    EXPECT_EQ(cf["coefficients"][i].get<double>(), stage.k[i]);
  }
  expectMeetsReported(cf, 101);
}

// The committed luts/gtso/gtso.json (what `gtbake export` ships), once it carries closed_form.
TEST(S3ClosedForm, ShippedLutsMeetTheirReportedError) {
  const std::filesystem::path path =
      std::filesystem::path(GTBAKE_SOURCE_DIR) / "luts/gtso/gtso.json";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  const nlohmann::json j = nlohmann::json::parse(in);
  if (!j.contains("closed_form")) {
    GTEST_SKIP() << path << " predates the closed form (regenerate luts/ with gtbake all)";
  }
  expectMeetsReported(j["closed_form"], 201);
}

}  // namespace
}  // namespace gtbake::gtso
