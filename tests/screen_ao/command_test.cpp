// `gtbake screen-ao` end to end on a small sweep: the output set and its files, and one-line
// errors with no output for bad input (docs/screen_ao.md, "Outputs").
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/output_set.h"
#include "gbuffer_scenes.h"
#include "scene/scene.h"
#include "screen_ao/screen_ao_command.h"
#include "screen_ao_errors.h"
#include "support/temp_dir.h"
#include "sweep/sweep_command.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

class ScreenAoCommand : public ::testing::Test {
 protected:
  ScreenAoCommand() : dir_("screen-ao") {}
  // A sweep of the corner field at 24×24 px, 16 walks.
  fs::path sweep() {
    const fs::path gltf = dir_.path() / "corner.gltf";
    writeGltfScene(gltf, test::cornerField(0.3));
    SweepOptions o;
    o.scenes = {gltf};
    o.out = dir_.path() / "sweep";
    o.spp = 16;
    o.width = 24;
    o.height = 24;
    o.specular_roughness = {};
    o.progress = false;
    runSweep(o);
    return o.out;
  }
  ScreenAoOptions options(const fs::path& sweep_dir, const std::string& out) {
    ScreenAoOptions o;
    o.sweep = sweep_dir;
    o.out = dir_.path() / out;
    o.progress = false;
    return o;
  }
  test::TempDir dir_;
};

TEST_F(ScreenAoCommand, WritesOneOutputSet) {
  ScreenAoOptions o = options(sweep(), "out");
  runScreenAo(o);
  const OutputManifest m = readOutputSet(o.out, "screen_ao");
  const nlohmann::json j = nlohmann::json::parse(m.readVerified("screen_ao.json"));
  ASSERT_EQ(j["estimators"].size(), 5u);
  const auto& bins = j["estimators"]["gtao-runtime"]["scenes"]["corner"]["bins"];
  ASSERT_EQ(bins.size(), 10u);
  EXPECT_EQ(j["estimators"]["hbao"]["radius_channel"], "A_R1");
  EXPECT_TRUE(j["convergence"]["rms_change"].is_number());
  std::size_t pixels = 0;
  for (const auto& b : bins) pixels += b["pixels"].get<std::size_t>();
  EXPECT_EQ(pixels, j["estimators"]["hbao"]["scenes"]["all"]["all"]["pixels"].get<std::size_t>());
  const ExrImage exr = decodeExr(m.readVerified("corner.exr"), "corner.exr");
  for (const std::string& name : screenAoEstimatorNames()) {
    for (const char* c : {".A", ".BNX", ".BNY", ".BNZ"})
      EXPECT_EQ(exr.channels.count(name + c), 1u);
    EXPECT_NE(m.find("corner_" + name + "_diff.png"), nullptr);
  }
  EXPECT_EQ(exr.channels.count("mask"), 1u);
  EXPECT_NE(m.find("screen_ao.html"), nullptr);
}

TEST_F(ScreenAoCommand, RejectsBadInput) {
  const fs::path swept = sweep();
  test::expectScreenAoError(options(dir_.path() / "nowhere", "a"), "does not exist");
  ScreenAoOptions bad = options(swept, "b");
  bad.settings.runtime.frames = 0;
  test::expectScreenAoError(bad, "frames");
  bad = options(swept, "c");
  bad.settings.reference.radius = -1.0;
  test::expectScreenAoError(bad, "radius");
  bad = options(swept, "d");
  applySetting(&bad.settings, "gtao-reference.refine_levels=17");
  test::expectScreenAoError(bad, "refine_levels");
  bad = options(swept, "e");
  applySetting(&bad.settings, "gtao-reference.refine_tolerance=0");
  test::expectScreenAoError(bad, "refine_tolerance");
  EXPECT_THROW(parseEstimatorList("gtao,hbao"), Error);
  EXPECT_THROW(parseEstimatorList("hbao,hbao"), Error);
  // Parsed once into the table's values, in the order given; "all" is the table's order.
  EXPECT_EQ(parseEstimatorList("hbao,gtao-runtime"),
            (std::vector<Estimator>{Estimator::kHbao, Estimator::kGtaoRuntime}));
  EXPECT_EQ(
      parseEstimatorList("all"),
      (std::vector<Estimator>{Estimator::kGtaoReference, Estimator::kGtaoRuntime, Estimator::kHbao,
                              Estimator::kBitmaskUniform, Estimator::kBitmaskCosine}));
  EXPECT_TRUE(parseEstimatorList("none").empty());
  EXPECT_EQ(estimatorListText(parseEstimatorList("bitmask-cosine,hbao"), "+"),
            "bitmask-cosine+hbao");
  ScreenAoSettings s;
  EXPECT_THROW(applySetting(&s, "hbao.directions=two"), Error);
  EXPECT_THROW(applySetting(&s, "hbao.thickness=1"), Error);
  EXPECT_THROW(applySetting(&s, "ssao.radius=1"), Error);
  EXPECT_THROW(applySetting(&s, "gtao-reference.steps_per_pixel=2"), Error);  // the search is exact
  applySetting(&s, "gtao-reference.refine_tolerance=0.004");
  EXPECT_EQ(s.reference.refine_tolerance, 0.004);
  EXPECT_THROW(applySetting(&s, "radius=1"), Error);
  applySetting(&s, "all.radius=0.5");
  EXPECT_EQ(s.bitmask_cosine.radius, 0.5);
}

TEST(GbufferChannels, MissingOrMismatchedChannelsAreOneLineErrors) {
  std::map<std::string, std::vector<float>> channels;
  for (const char* c : {"mask", "Z", "NX", "NY", "NZ"}) channels[c] = std::vector<float>(4, 0.0f);
  const PerspectiveCamera camera;
  channels.erase("Z");
  try {
    gbufferFromChannels(2, 2, camera, channels, "old.exr");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no channel Z"), std::string::npos) << e.what();
  }
  channels["Z"] = std::vector<float>(3, 1.0f);
  EXPECT_THROW(gbufferFromChannels(2, 2, camera, channels, "short.exr"), Error);
}

}  // namespace
}  // namespace gtbake
