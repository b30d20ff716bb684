// validate-gtso on a screen-space estimator's inputs (docs/validate_gtso.md §6): the methods read
// the estimator's Â and b̂ exactly as screen-ao stored them, checked against a brute-force
// evaluation from the EXR channels with the plain cone of gtso/cone_intersection.h; bad screen-ao
// sets and a missing ray-traced run are one-line errors that write nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "common/image_io.h"
#include "gtso/cone_intersection.h"
#include "reliability/reliability_fixtures.h"
#include "screen_ao/screen_ao_command.h"
#include "support/test_scenes.h"
#include "sweep/sweep_command.h"
#include "validate_gtso/specular_methods.h"
#include "validate_gtso/validate_gtso_command.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

constexpr double kRoughness[] = {0.25, 0.6};

// Three small scenes swept with specular channels, screen-ao (gtao-runtime, hbao) on them, a
// baked table set and the ray-traced validate-gtso run in it (whose u the estimator runs score).
struct EstimatorFixture {
  TempDir dir{"validate_gtso_estimator"};
  test::ExportFixture tables;
  fs::path sweep = dir.path() / "sweep";
  fs::path screen_ao = dir.path() / "screen_ao";
  fs::path luts = tables.root.path();
  EstimatorFixture() {
    writeGltfScene(dir.path() / "scenes" / "box.gltf", makeClosedBoxScene());
    writeGltfScene(dir.path() / "scenes" / "deep.gltf", makeSphericalCavityScene(1.0, 0.7));
    writeGltfScene(dir.path() / "scenes" / "shallow.gltf", makeSphericalCavityScene(1.0, 0.4));
    SweepOptions s;
    s.scenes = {dir.path() / "scenes"};
    s.out = sweep;
    s.spp = 8;
    s.width = s.height = 32;
    s.bounces = 1;
    s.specular_roughness = {kRoughness[0], kRoughness[1]};
    s.specular_spp = 4;
    s.threads = 1;
    s.progress = false;
    runSweep(s);
    ScreenAoOptions a;
    a.sweep = sweep;
    a.out = screen_ao;
    a.estimators = {Estimator::kGtaoRuntime, Estimator::kHbao};
    a.threads = 1;
    a.progress = false;
    runScreenAo(a);
    tables.encode(luts / "encode");  // the layout of docs/reproducibility.md "Layout"
    ValidateGtsoOptions v = options("");
    v.out = luts / "validate_gtso";
    runValidateGtso(v);
  }
  ValidateGtsoOptions options(const std::string& estimator) const {
    ValidateGtsoOptions v;
    v.sweep = sweep;
    v.luts = luts;
    v.input.estimator = estimator;
    v.input.unbounded_truth = true;  // the brute force below reads the unbounded S channels
    v.input.screen_ao = screen_ao;
    v.write_images = false;
    v.print_summary = false;
    v.progress = false;
    return v;
  }
};

const EstimatorFixture& fixture() {
  static const EstimatorFixture f;
  return f;
}

nlohmann::json readJson(const fs::path& path) {
  return nlohmann::json::parse(test::readBytes(path));
}

struct Rmse {
  double sum2 = 0.0;
  std::size_t n = 0;
  void add(double e) {
    sum2 += e * e;
    ++n;
  }
  double value() const { return std::sqrt(sum2 / static_cast<double>(n)); }
};

// S = Â, the cone at u = 0.01 floored at Â² and Lagarde, each from the EXR channels by hand.
struct BruteForce {
  Rmse ao, cone_ao2, lagarde;
};

BruteForce bruteForce(const fs::path& sweep, const fs::path& screen_ao,
                      const std::string& estimator) {
  BruteForce out;
  for (const char* name : {"box", "deep", "shallow"}) {
    const ExrImage sw = readExr(sweep / (std::string(name) + ".exr"));
    const ExrImage est = readExr(screen_ao / (std::string(name) + ".exr"));
    const auto ch = [&](const ExrImage& im, const std::string& c) -> const std::vector<float>& {
      return im.channel(c, name);
    };
    for (std::size_t p = 0; p < ch(sw, "mask").size(); ++p) {
      if (!(ch(sw, "mask")[p] > 0.5f)) continue;
      const double A = std::clamp(static_cast<double>(ch(est, estimator + ".A")[p]), 0.0, 1.0);
      const double n[3] = {ch(sw, "NX")[p], ch(sw, "NY")[p], ch(sw, "NZ")[p]};
      const double v[3] = {ch(sw, "VX")[p], ch(sw, "VY")[p], ch(sw, "VZ")[p]};
      const double b[3] = {ch(est, estimator + ".BNX")[p], ch(est, estimator + ".BNY")[p],
                           ch(est, estimator + ".BNZ")[p]};
      const double nv = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
      double r[3], br = 0.0, rr = 0.0;
      for (int c = 0; c < 3; ++c) r[c] = 2.0 * nv * n[c] - v[c];
      for (int c = 0; c < 3; ++c) br += b[c] * r[c], rr += r[c] * r[c];
      const double beta = std::acos(std::clamp(br / std::sqrt(rr), -1.0, 1.0));
      for (double rp : kRoughness) {
        const std::string channel = rp == kRoughness[0] ? "S025" : "S060";
        const double truth = ch(sw, channel)[p];
        const double alpha = rp * rp;
        const double cone = gtso::coneSpecularOcclusion(
            std::acos(std::sqrt(1.0 - A)), gtso::specularConeAperture(gtso::kPaperU, alpha), beta);
        const double lagarde =
            std::clamp(std::pow(nv + A, std::exp2(-16.0 * alpha - 1.0)) - 1.0 + A, 0.0, 1.0);
        out.ao.add(A - truth);
        out.cone_ao2.add(std::max(cone, A * A) - truth);
        out.lagarde.add(lagarde - truth);
      }
    }
  }
  return out;
}

TEST(ValidateGtsoEstimator, MethodsReadTheEstimatesAsStored) {
  const EstimatorFixture& f = fixture();
  for (const std::string estimator : {"gtao-runtime", "hbao"}) {
    ValidateGtsoOptions v = f.options(estimator);
    v.out = f.dir.path() / ("est_" + estimator);
    const ValidateGtsoResult result = runValidateGtso(v);
    const nlohmann::json j = readJson(result.json);
    EXPECT_EQ(j["input"]["estimator"], estimator);
    EXPECT_EQ(j["u"]["fitted"].get<double>(),
              readJson(f.luts / "validate_gtso" / "validate_gtso.json")["u"]);
    EXPECT_FALSE(j.contains("u_fit")) << "u is fitted on the ray-traced inputs only";
    const BruteForce brute = bruteForce(f.sweep, f.screen_ao, estimator);
    const nlohmann::json& overall = j["overall"];
    EXPECT_EQ(overall["S_A"]["count"].get<std::size_t>(), brute.ao.n);
    // Values are stored as float: 3e-8 each, far below 2e-6 in an RMSE of ~0.1–0.5.
    EXPECT_NEAR(overall["S_A"]["rmse"].get<double>(), brute.ao.value(), 2e-6) << estimator;
    EXPECT_NEAR(overall["cone_ao2_u_0.01"]["rmse"].get<double>(), brute.cone_ao2.value(), 2e-6)
        << estimator;
    EXPECT_NEAR(overall["lagarde"]["rmse"].get<double>(), brute.lagarde.value(), 2e-6) << estimator;
    // The ray-traced run scores another A: the replacement took place.
    const nlohmann::json traced = readJson(f.luts / "validate_gtso" / "validate_gtso.json");
    EXPECT_NE(overall["S_A"]["rmse"], traced["overall"]["S_A"]["rmse"]);
  }
}

// Against the near-field S_R (the default) the unbounded comparison sits beside it: the same
// values scored against the unbounded S, so exactly what a run with --truth unbounded reports; and
// since S_R ≥ S sample by sample (the same walks, the sky beyond R), "no occlusion" (S = 1) is
// never further from S_R than from S.
TEST(ValidateGtsoEstimator, NearFieldTruthKeepsTheUnboundedComparisonBesideIt) {
  const EstimatorFixture& f = fixture();
  ValidateGtsoOptions near = f.options("hbao");
  near.input.unbounded_truth = false;
  near.out = f.dir.path() / "near_hbao";
  const nlohmann::json n = readJson(runValidateGtso(near).json);
  ValidateGtsoOptions far = f.options("hbao");
  far.out = f.dir.path() / "far_hbao";
  const nlohmann::json u = readJson(runValidateGtso(far).json);
  EXPECT_EQ(n["truth"]["kind"], "near-field");
  EXPECT_EQ(n["truth"]["radius"], 1.0);
  EXPECT_EQ(u["truth"]["kind"], "unbounded");
  EXPECT_FALSE(u.contains("unbounded_truth"));
  ASSERT_TRUE(n.contains("unbounded_truth"));
  for (const auto& [method, stats] : u["overall"].items()) {
    EXPECT_EQ(n["unbounded_truth"]["overall"][method]["rmse"], stats["rmse"]) << method;
    EXPECT_EQ(n["unbounded_truth"]["per_roughness"]["S025"][method]["rmse"],
              u["per_roughness"]["S025"][method]["rmse"])
        << method;
  }
  EXPECT_LT(n["overall"]["S_1"]["rmse"].get<double>(),
            n["unbounded_truth"]["overall"]["S_1"]["rmse"].get<double>());
}

TEST(ValidateGtsoEstimator, AoSquaredFloorByHand) {
  EXPECT_EQ(coneAo2(0.2, 0.5), 0.25);
  EXPECT_EQ(coneAo2(0.7, 0.5), 0.7);
  EXPECT_EQ(coneAo2(0.0, 1.0), 1.0);  // an open pixel is never darkened
}

TEST(ValidateGtsoEstimator, BadInputsAreOneLineErrorsAndWriteNothing) {
  const EstimatorFixture& f = fixture();
  const fs::path out = f.dir.path() / "refused";
  ValidateGtsoOptions v = f.options("gtao-runtime");
  v.out = out;
  v.u = 0.05;
  EXPECT_ERROR(runValidateGtso(v), "--u scores the ray-traced inputs");
  v = f.options("bitmask-cosine");  // not in this screen-ao set
  v.out = out;
  EXPECT_ERROR(runValidateGtso(v), "has no estimator 'bitmask-cosine'");
  // Tables without the ray-traced run: no u to score.
  const TempDir bare("validate_gtso_bare_luts");
  f.tables.encode(bare.path() / "encode");
  fs::copy(f.tables.gtso, bare.path() / "gtso", fs::copy_options::recursive);
  v = f.options("hbao");
  v.luts = bare.path();
  v.out = out;
  EXPECT_ERROR(runValidateGtso(v), "run `gtbake validate-gtso` on the ray-traced inputs first");
  // screen-ao of another sweep of the same scenes (another size): its masks are not the sweep's.
  SweepOptions s;
  s.scenes = {f.dir.path() / "scenes"};
  s.out = f.dir.path() / "other_sweep";
  s.spp = 2;
  s.width = s.height = 24;
  s.specular_roughness = {};
  s.threads = 1;
  s.progress = false;
  runSweep(s);
  ScreenAoOptions a;
  a.sweep = s.out;
  a.out = f.dir.path() / "other_screen_ao";
  a.estimators = {Estimator::kHbao};
  a.threads = 1;
  a.progress = false;
  runScreenAo(a);
  v = f.options("hbao");
  v.input.screen_ao = a.out;
  v.out = out;
  EXPECT_ERROR(runValidateGtso(v), "screen-ao was run on another sweep");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace gtbake
