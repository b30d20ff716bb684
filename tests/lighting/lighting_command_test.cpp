// gtbake lighting end to end on a small sweep (docs/lighting.md §3): the uniform sky reproduces
// the white-sky G exactly, a one-sided window makes the engine's product glow, the outputs form
// one set, and bad input is one line with nothing written.
#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/output_set.h"
#include "common/threads.h"
#include "fit/multibounce_fit.h"
#include "fit/sweep_data.h"
#include "lighting/lighting_command.h"
#include "scene/scene.h"
#include "support/test_scenes.h"
#include "sweep/sweep_command.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

class LightingCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("gtbake_test_lighting_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "scenes");
    writeGltfScene(root_ / "scenes" / "spheres.gltf", makeSphereOnPlaneScene(1.0));
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path sweep(bool transfer) {
    SweepOptions o;
    o.scenes = {root_ / "scenes"};
    o.out = root_ / (transfer ? "sweep" : "sweep_off");
    o.spp = 16;
    o.width = 40;
    o.height = 30;
    o.specular_roughness = {};
    o.transfer = transfer;
    o.progress = false;
    runSweep(o);
    return o.out;
  }

  void expectRejected(const LightingOptions& o, const std::string& fragment) {
    try {
      runLighting(o);
      ADD_FAILURE() << "accepted: " << fragment;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(fragment), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
    EXPECT_FALSE(fs::exists(o.out)) << fragment;
  }

  fs::path root_;
};

TEST_F(LightingCommand, UniformSkyIsTheWhiteSkyAndAWindowGlows) {
  LightingOptions o;
  o.sweep = sweep(true);
  o.environments = {"uniform", "window"};
  o.out = root_ / "lighting";
  o.print_summary = false;
  runLighting(o);
  const OutputManifest manifest = readOutputSet(o.out, "lighting");
  const nlohmann::json j = manifest.readVerifiedJson("lighting.json");
  ASSERT_EQ(j["environments"].size(), 2u);
  const nlohmann::json& uniform = j["environments"][0];
  EXPECT_EQ(uniform["name"], "uniform");
  for (const auto& a : uniform["models"]["white_sky_exact"]["per_albedo"]) {
    EXPECT_LT(a["rmse"].get<double>(), 1e-6);
    EXPECT_GT(a["pixels"].get<int>(), 100);
  }
  // Under the uniform sky the refit reads the points `gtbake fit` reads (docs/lighting.md §3).
  const MultiBounceFit fit = fitMultiBounce(loadSweep(o.sweep));
  for (int c = 0; c < 6; ++c) {
    EXPECT_NEAR(uniform["refit"]["coefficients"][c].get<double>(), fit.linear.coeffs[c], 1e-4) << c;
  }
  const nlohmann::json& window = j["environments"][1];
  EXPECT_GT(window["models"]["paper"]["per_albedo"][4]["glow_share"].get<double>(), 0.0);
  EXPECT_EQ(window["models"]["paper"]["per_a_bin"].size(), 10u);
  EXPECT_EQ(window["models"]["paper"]["per_type"].size(), 1u);
  EXPECT_TRUE(window["refit"]["available"].get<bool>());
  EXPECT_FALSE(window["refit"]["scene_band"].get<bool>());  // one scene: no jackknife
  EXPECT_NE(manifest.find("lighting.html"), nullptr);
  EXPECT_NE(manifest.find("images/window_spheres.png"), nullptr);
}

// The environments run side by side (docs/lighting.md §3): every output byte is the same on one
// thread and on two.
TEST_F(LightingCommand, SameBytesOnOneAndTwoThreads) {
  const fs::path swept = sweep(true);
  std::vector<std::string> json, page;
  for (int threads : {1, 2}) {
    const ThreadLimit limit(threads);
    LightingOptions o;
    o.sweep = swept;
    o.environments = {"uniform", "overcast", "horizon", "sun-sky", "window"};
    o.out = root_ / ("lighting_" + std::to_string(threads));
    o.print_summary = false;
    runLighting(o);
    const OutputManifest manifest = readOutputSet(o.out, "lighting");
    json.push_back(manifest.readVerified("lighting.json"));
    page.push_back(manifest.readVerified("lighting.html"));
  }
  EXPECT_EQ(json[0], json[1]);
  EXPECT_EQ(page[0], page[1]);
}

TEST_F(LightingCommand, BadInputIsOneLineAndWritesNothing) {
  LightingOptions o;
  o.sweep = sweep(false);
  o.environments = {"uniform"};
  o.out = root_ / "lighting";
  expectRejected(o, "no transfer channels");
  o.sweep = root_ / "sweep_off";
  o.environments = {"dusk"};
  expectRejected(o, "dusk");
  o.environments = {"uniform", "uniform"};
  expectRejected(o, "two environments are named 'uniform'");
  o.environments = {(root_ / "missing.exr").string()};
  expectRejected(o, "missing.exr");
  o.environments = {};
  expectRejected(o, "no environment");
}

}  // namespace
}  // namespace gtbake
