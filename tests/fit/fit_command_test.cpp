// runFit / runValidate end to end on sweep directories written with writeExr, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/output_set.h"
#include "fit/fit_command.h"
#include "fit/fit_errors.h"
#include "fit/multibounce_fit.h"
#include "fit/scene_jackknife.h"
#include "synthetic_sweep.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kBounces = 3;

// A valid cavity-law sweep, written once and copied by each test that needs one.
const fs::path& cavitySweep() {
  static const fs::path dir = [] {
    const fs::path d = test::freshDir("cavity_sweep");
    test::writeWalkSweep(
        d, {"bowl", "pit"}, 96, 96, 64, kBounces,
        [](double u) { return test::cavityLaw(u, kBounces); }, 5);
    return d;
  }();
  return dir;
}

fs::path copyOfSweep(const std::string& name) {
  const fs::path dir = test::freshDir(name);
  fs::copy(cavitySweep(), dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  return dir;
}

json readJson(const fs::path& path) {
  return json::parse(readFile(path));
}

MultiBounceCoeffs linearFromJson(const json& j) {
  return {j["a1"], j["a0"], j["b1"], j["b0"], j["c1"], j["c0"]};
}

// The refit of a sweep drawn from the cavity law lands on the law's own two-stage fit within its
// Monte Carlo uncertainty: max over (A, ρ) of |G_refit − G_law| / SE_MC(G) (the Monte Carlo band
// from the fit's own covariance) stays below 4. The sweep's pixels sample A on the law's grid (bar
// the masked first row, A < 0.011), so what separates the two is the walks' noise.
TEST(FitCommand, CavityLawRefitMatchesItsOwnCubicWithinMonteCarloError) {
  const fs::path out = test::freshDir("cavity_fit") / "fit.json";
  FitOptions options;
  options.sweep = cavitySweep();
  options.out = out;
  options.progress = false;
  const FitResult result = runFit(options);
  const json doc = readJson(out);
  const MultiBounceCoeffs refit = linearFromJson(doc["linear"]);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(refit[i], result.linear[i]);
  const MultiBounceFit fit = fitMultiBounce(loadSweep(cavitySweep()));
  const MultiBounceCoeffs law = test::cavityLawOwnFit(kBounces);
  double worst = 0.0;
  for (double A = 0.05; A <= 1.0; A += 0.05) {
    for (double rho = 0.1; rho <= 0.9001; rho += 0.1) {
      const double se = curveBand(fit.linear.mc_covariance, A, rho);
      worst = std::max(
          worst, std::abs(evalMultiBounce(refit, A, rho) - evalMultiBounce(law, A, rho)) / se);
    }
  }
  EXPECT_LT(worst, 4.0);
  for (const char* key :
       {"settings", "per_albedo", "linear", "linear_se", "scene_jackknife", "rho_line_lack_of_fit",
        "open_surface", "constrain_open_alternative", "weighting_alternatives", "view_weights",
        "floor", "errors", "shipped", "eiv_bias", "sweep", "version"}) {
    EXPECT_TRUE(doc.contains(key)) << key;
  }
  // Two scenes: no scene-level band, and fit.json says why.
  EXPECT_FALSE(doc["scene_jackknife"]["available"].get<bool>());
  EXPECT_NE(doc["scene_jackknife"]["message"].get<std::string>().find("at least 3"),
            std::string::npos);
  EXPECT_EQ(doc["per_albedo"].size(), test::kAlbedos.size());
  EXPECT_EQ(doc["errors"]["refit"]["per_view"].size(), 2u);
  for (std::size_t v = 0; v < 2; ++v) {  // per-view rows name their view (docs/scenes.md)
    EXPECT_EQ(doc["errors"]["refit"]["per_view"][v]["view"], doc["sweep"]["views"][v]);
    EXPECT_EQ(doc["floor"]["per_view"][v]["view"], doc["sweep"]["views"][v]);
    EXPECT_EQ(doc["view_weights"][v]["view"], doc["sweep"]["views"][v]);
  }
  EXPECT_EQ(doc["sweep"]["points"].get<std::size_t>(), 2u * 96 * 95);
  const fs::path report = out.parent_path() / "report";
  EXPECT_TRUE(fs::is_regular_file(report / "index.html"));
  EXPECT_TRUE(fs::is_regular_file(report / "fig6_bowl.svg"));
  EXPECT_TRUE(fs::is_regular_file(report / "fig7_b.svg"));
  EXPECT_TRUE(fs::is_regular_file(report / "refit_vs_shipped.svg"));
}

// fit.json's shipped error table, errorTable() and validate's printed RMSE are the same numbers.
TEST(FitCommand, FitAndValidateAgreeOnThePapersErrors) {
  const fs::path out = test::freshDir("agree_fit") / "fit.json";
  FitOptions options;
  options.sweep = cavitySweep();
  options.out = out;
  options.progress = false;
  runFit(options);
  const json shipped = readJson(out)["errors"]["shipped"];
  const ErrorTable table = errorTable(loadSweep(cavitySweep()), kPaperCoeffs);
  EXPECT_DOUBLE_EQ(shipped["rmse"].get<double>(), table.rmse);
  EXPECT_DOUBLE_EQ(shipped["max_abs"].get<double>(), table.max_abs);

  ValidateOptions validate;
  validate.sweep = cavitySweep();
  validate.progress = false;
  testing::internal::CaptureStdout();
  runValidate(validate);
  std::fflush(stdout);
  const std::string printed = testing::internal::GetCapturedStdout();
  // validate's RMSE comes from the binned sums of validate_data.h (exact to ~1e-13).
  char all_line[128];
  std::snprintf(all_line, sizeof(all_line), "%-14s %9.5f", "all", table.rmse);
  EXPECT_NE(printed.find(all_line), std::string::npos) << printed;
}

TEST(FitCommand, ValidateRejectsNonFiniteCoefficients) {
  ValidateOptions validate;
  validate.sweep = cavitySweep();
  validate.progress = false;
  validate.coeffs[3] = std::nan("");
  EXPECT_THROW(runValidate(validate), Error);
}

// Runs the fit on `dir` and expects a one-line gtbake::Error containing `needle`, no fit.json.
void expectFitError(const fs::path& dir, const std::string& needle) {
  const fs::path out = test::freshDir("bad_out") / "fit.json";
  FitOptions options;
  options.sweep = dir;
  options.out = out;
  options.progress = false;
  try {
    runFit(options);
    ADD_FAILURE() << "no error for " << needle;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(needle), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_FALSE(fs::exists(out));
}

void editJson(const fs::path& dir, const std::function<void(json&)>& edit) {
  json doc = readJson(dir / "sweep.json");
  edit(doc);
  writeFileAtomically(dir / "sweep.json", doc.dump());
  resealOutputSet(dir, "sweep");  // exercise loadSweep's own checks, not the manifest's
}

void editExr(const fs::path& file, const std::function<void(ExrImage&)>& edit) {
  ExrImage image = readExr(file);
  edit(image);
  std::vector<ExrChannel> channels;
  for (const auto& [name, pixels] : image.channels) channels.push_back({name, pixels});
  writeExr(file, image.width, image.height, channels, image.attributes);
  resealOutputSet(file.parent_path(), "sweep");
}

TEST(FitCommand, BadInputIsAOneLineError) {
  expectFitError(test::freshDir("nowhere") / "missing", "does not exist");
  expectFitError(test::freshDir("empty"), "no sweep.json");

  fs::path dir = copyOfSweep("malformed");
  writeFileAtomically(dir / "sweep.json", "{\"settings\": [1, 2");
  resealOutputSet(dir, "sweep");
  expectFitError(dir, "malformed JSON");

  dir = copyOfSweep("exr_missing");
  fs::remove(dir / "pit.exr");
  expectFitError(dir, "pit.exr is missing");

  dir = copyOfSweep("channel_missing");
  editExr(dir / "bowl.exr", [](ExrImage& image) { image.channels.erase("H1.P2"); });
  expectFitError(dir, "H1.P2");

  dir = copyOfSweep("size_mismatch");
  editJson(dir, [](json& doc) { doc["views"][1]["width"] = 95; });
  expectFitError(dir, "does not match");

  dir = copyOfSweep("nan");
  editExr(dir / "bowl.exr", [](ExrImage& image) { image.channels["H0.P1"][96 * 50 + 3] = NAN; });
  expectFitError(dir, "non-finite");

  dir = copyOfSweep("albedo_unknown");
  editJson(dir, [](json& doc) { doc["settings"]["albedos"][2] = 0.35; });
  expectFitError(dir, "G035");

  dir = copyOfSweep("albedo_unlisted");
  editJson(dir, [](json& doc) { doc["settings"]["albedos"].erase(6); });
  expectFitError(dir, "G090");

  dir = copyOfSweep("albedo_inconsistent");
  editExr(dir / "pit.exr", [](ExrImage& image) {
    for (float& g : image.channels["G030"]) g += 0.01f;
  });
  expectFitError(dir, "inconsistent with albedo");

  dir = copyOfSweep("unmasked_count");
  editJson(dir, [](json& doc) { doc["views"][0]["unmasked_pixels"] = 5; });
  expectFitError(dir, "unmasked pixels");

  dir = test::freshDir("too_few");
  test::writeWalkSweep(
      dir, {"tiny"}, 20, 20, 8, kBounces, [](double u) { return test::cavityLaw(u, kBounces); }, 3);
  expectFitError(dir, "at least 1000");
}

// A NaN in a masked pixel is not an error: masked pixels are never read.
TEST(FitCommand, NanInMaskedPixelIsIgnored) {
  const fs::path dir = copyOfSweep("nan_masked");
  editExr(dir / "bowl.exr", [](ExrImage& image) { image.channels["A"][5] = NAN; });
  EXPECT_NO_THROW(loadSweep(dir));
}

}  // namespace
}  // namespace gtbake
