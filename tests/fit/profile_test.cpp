// Equation 10 on a screen-space estimate (docs/profiles.md): the regressor substitution against
// the cavity law's own fit on the same regressor, the held-out table against brute-force refits,
// and the screen-ao set's bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/output_set.h"
#include "fit/fit_analysis.h"
#include "fit/fit_command.h"
#include "fit/fit_errors.h"
#include "fit/multibounce_fit.h"
#include "fit/screen_estimate.h"
#include "synthetic_sweep.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kBounces = 3;
constexpr int kSide = 64;
const std::vector<std::string> kScenes = {"bowl", "pit", "well", "groove"};

// A cavity-law sweep of four scenes (writeWalkSweep: pixel i has A = (i + 0.5)/pixels exactly,
// the first row masked).
const fs::path& profileSweep() {
  static const fs::path dir = [] {
    const fs::path d = test::freshDir("profile_sweep");
    test::writeWalkSweep(
        d, kScenes, kSide, kSide, 64, kBounces,
        [](double u) { return test::cavityLaw(u, kBounces); }, 11);
    return d;
  }();
  return dir;
}

// A screen-ao output set beside nothing but its own files: for each scene an EXR whose
// `<estimator>.A` is estimate(A) of the sweep's exact per-pixel A, with the sweep's mask.
fs::path writeScreenAoSet(const std::string& name, const std::string& estimator,
                          const std::function<double(double)>& estimate,
                          const std::vector<std::string>& scenes = kScenes) {
  const fs::path dir = test::freshDir(name);
  const std::size_t pixels = kSide * kSide;
  json doc;
  doc["images"] = json::array();
  doc["estimators"] = {{estimator, json::object()}};
  std::vector<std::string> files;
  for (const std::string& scene : scenes) {
    std::vector<float> a(pixels), mask(pixels, 1.0f);
    for (std::size_t i = 0; i < pixels; ++i) {
      if (i < static_cast<std::size_t>(kSide)) mask[i] = 0.0f;
      a[i] = static_cast<float>(estimate((i + 0.5) / pixels));
    }
    writeExr(dir / (scene + ".exr"), kSide, kSide, {{estimator + ".A", a}, {"mask", mask}});
    doc["images"].push_back({{"name", scene}, {"file", scene + ".exr"}});
    files.push_back(scene + ".exr");
  }
  writeFileAtomically(dir / "screen_ao.json", doc.dump(2));
  files.push_back("screen_ao.json");
  sealOutputSet(dir, "screen_ao", files);
  return dir;
}

FitResult fitOn(const fs::path& screen_ao, const std::string& estimator, const fs::path& out) {
  FitOptions options;
  options.sweep = profileSweep();
  options.out = out;
  options.input = {estimator, screen_ao, true};  // the synthetic sweep has no near-field truth
  options.write_report = false;                  // as gtbake all writes profiles
  options.progress = false;
  return runFit(options);
}

// max over (A, ρ) of |G_a − G_b| / SE_MC(G) of `fit` (the Monte Carlo band of G's own noise).
double worstInMonteCarloBands(const MultiBounceCoeffs& a, const MultiBounceCoeffs& b,
                              const MultiBounceFit& fit) {
  double worst = 0.0;
  for (double A = 0.05; A <= 1.0; A += 0.05) {
    for (double rho = 0.1; rho <= 0.9001; rho += 0.1) {
      const double se = curveBand(fit.linear.mc_covariance, A, rho);
      worst =
          std::max(worst, std::abs(evalMultiBounce(a, A, rho) - evalMultiBounce(b, A, rho)) / se);
    }
  }
  return worst;
}

MultiBounceCoeffs linearOf(const json& j) {
  return {j["a1"], j["a0"], j["b1"], j["b0"], j["c1"], j["c0"]};
}

// An estimator that reads A² (darker than the truth everywhere): the profile fitted on it lands
// on the law's own least-squares cubic in Â = A², within G's Monte Carlo noise, and far from the
// law's cubic in A (the ray-traced fit's target), which the paper-style fit would keep.
TEST(Profile, FitOnABiasedEstimateFindsTheLawsCubicInThatEstimate) {
  const auto square = [](double A) { return A * A; };
  const fs::path screen = writeScreenAoSet("screen_square", "hbao", square);
  const fs::path out = test::freshDir("profile_square") / "fit.json";
  const FitResult result = fitOn(screen, "hbao", out);
  const json doc = json::parse(readFile(out));
  EXPECT_FALSE(fs::exists(out.parent_path() / "report"));
  EXPECT_EQ(doc["input"]["A"], "screen-space");
  EXPECT_EQ(doc["input"]["estimator"], "hbao");
  const MultiBounceCoeffs refit = linearOf(doc["linear"]);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(refit[i], result.linear[i]);

  SweepData data = loadSweep(profileSweep());
  useScreenEstimate(&data, {"hbao", screen});
  FitSettings settings;
  settings.eiv_correction = false;
  const MultiBounceFit fit = fitMultiBounce(data, settings);
  // The regressor substitution, on the unconstrained alternative (the profile itself is
  // shape-constrained, docs/profiles.md §7).
  const MultiBounceCoeffs free = linearOf(doc["unconstrained_alternative"]["linear"]);
  EXPECT_LT(worstInMonteCarloBands(free, test::cavityLawOwnFit(kBounces, square), fit), 4.0);
  EXPECT_GT(worstInMonteCarloBands(free, test::cavityLawOwnFit(kBounces), fit), 40.0);
  EXPECT_TRUE(doc["settings"]["shape_constrained"].get<bool>());
  EXPECT_TRUE(shapeChecks(refit).pass());
  EXPECT_TRUE(doc["profile"]["solver"]["converged"].get<bool>());
  EXPECT_EQ(doc["profile"]["gate"]["shipped"].get<bool>(),
            doc["errors"]["held_out_by_scene"]["rmse"].get<double>() <
                doc["errors"]["shipped"]["rmse"].get<double>());
  // Â carries no sampling noise: the correction for noise in A is off, and fit.json says so.
  EXPECT_FALSE(doc["settings"]["eiv_correction"].get<bool>());
  EXPECT_GT(result.held_out_rmse, result.rmse);
}

// The held-out table scores each scene with the refit that left it out: the same numbers as
// refitting from scratch on the other scenes and scoring that scene alone.
TEST(Profile, HeldOutErrorsEqualBruteForceLeaveOneSceneOutRefits) {
  const SweepData data = test::pooledSweep({{"a", {2.40, -0.30, 5.20, -0.60, 2.90, 0.70}, 3000},
                                            {"b", {2.10, -0.20, 4.90, -0.50, 2.80, 0.72}, 2500},
                                            {"c", {2.60, -0.35, 5.40, -0.65, 2.95, 0.69}, 3500},
                                            {"d", {2.30, -0.25, 5.00, -0.55, 2.85, 0.71}, 2000}},
                                           0.01, 0.01, 0.3, 5);
  for (bool constrained : {false, true}) {  // a profile's replicas are shape-constrained too
    FitSettings settings;
    settings.shape_constrained = constrained;
    const MultiBounceFit fit = fitMultiBounce(data, settings);
    const SceneJackknife jk = sceneJackknife(data, fit, kPaperCoeffs);
    const std::optional<ErrorTable> held = heldOutErrors(data, jk);
    ASSERT_TRUE(held.has_value());
    ASSERT_EQ(held->per_scene.size(), data.scenes.size());
    double sum2 = 0.0;
    std::size_t count = 0;
    for (std::size_t s = 0; s < data.scenes.size(); ++s) {
      SweepData rest, alone;
      for (std::size_t t = 0; t < data.scenes.size(); ++t) {
        test::appendScene(data, t, t == s ? alone : rest);
      }
      const MultiBounceCoeffs without = fitMultiBounce(rest, settings).linear.coeffs;
      const ErrorTable own = errorTable(alone, without);
      EXPECT_NEAR(held->per_scene[s].rmse, own.rmse, 1e-9 * own.rmse) << data.scenes[s].name;
      EXPECT_NEAR(held->per_scene[s].max_abs, own.max_abs, 1e-9 * own.max_abs);
      const std::size_t n = (data.scenes[s].end - data.scenes[s].begin) * data.albedos.size();
      sum2 += own.rmse * own.rmse * static_cast<double>(n);
      count += n;
    }
    EXPECT_NEAR(held->rmse, std::sqrt(sum2 / static_cast<double>(count)), 1e-9 * held->rmse);
    EXPECT_GT(held->rmse, errorTable(data, fit.linear.coeffs).rmse);
  }
}

void expectFitError(const fs::path& screen, const std::string& estimator, const char* needle) {
  try {
    fitOn(screen, estimator, test::freshDir("profile_bad") / "fit.json");
    ADD_FAILURE() << "no error for " << needle;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(Profile, BadScreenAoSetsGiveOneLineErrors) {
  const auto identity = [](double A) { return A; };
  const fs::path good = writeScreenAoSet("screen_good", "hbao", identity);
  expectFitError(good, "bitmask-uniform", "has no estimator 'bitmask-uniform'");
  expectFitError(writeScreenAoSet("screen_short", "hbao", identity, {"bowl", "pit", "well"}),
                 "hbao", "has no image 'groove'");
  expectFitError(writeScreenAoSet("screen_range", "hbao", [](double A) { return 1.5 * A; }), "hbao",
                 "outside [0, 1]");
  expectFitError(test::freshDir("screen_none"), "hbao", "has no complete");
  // A file changed after screen-ao wrote it is refused by the manifest.
  const fs::path edited = writeScreenAoSet("screen_edited", "hbao", identity);
  std::vector<float> a(kSide * kSide, 0.5f), mask(kSide * kSide, 1.0f);
  writeExr(edited / "pit.exr", kSide, kSide, {{"hbao.A", a}, {"mask", mask}});
  expectFitError(edited, "hbao", "does not match screen_ao.manifest.json");
  // The same images with another mask: screen-ao ran on another sweep.
  const fs::path other = writeScreenAoSet("screen_mask", "hbao", identity);
  writeExr(other / "well.exr", kSide, kSide, {{"hbao.A", a}, {"mask", mask}});
  resealOutputSet(other, "screen_ao");
  expectFitError(other, "hbao", "screen-ao was run on another sweep");
}

}  // namespace
}  // namespace gtbake
