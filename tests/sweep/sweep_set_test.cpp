// sweep/sweep_set: the one reader of sweep.json (docs/sweep.md "Outputs"): typed settings and
// views with the fallbacks of sweeps before views, and one-line errors for what `gtbake sweep`
// never writes.
#include "sweep/sweep_set.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_set.h"
#include "support/temp_dir.h"

namespace gtbake {
namespace {

using nlohmann::json;

json validDoc() {
  return json{{"gtbake_version", "0.1.0"},
              {"settings",
               {{"spp", 64},
                {"width", 16},
                {"height", 8},
                {"bounces", 3},
                {"radius", nullptr},
                {"seed", 7},
                {"albedos", {0.1, 0.5, 0.9}},
                {"specular_roughness", {0.125, 0.5}},
                {"specular_spp", 16},
                {"gbuffer_radii", {0.5, 1.0}}}},
              {"views",
               {{{"name", "a"},
                 {"scene", "room"},
                 {"type", "box"},
                 {"file", "a.exr"},
                 {"width", 16},
                 {"height", 8},
                 {"unmasked_pixels", 100}},
                {{"name", "b"}, {"file", "b.exr"}}}}};
}

// Writes `doc` as a sealed sweep (the EXRs are not read by the set) and reads it back.
SweepSet readDoc(const test::TempDir& dir, const json& doc) {
  writeFileAtomically(dir.path() / "sweep.json", doc.dump());
  writeFileAtomically(dir.path() / "a.exr", "a");
  writeFileAtomically(dir.path() / "b.exr", "b");
  sealOutputSet(dir.path(), "sweep", {"sweep.json", "a.exr", "b.exr"});
  return readSweepSet(dir.path());
}

std::string errorOf(const json& doc) {
  const test::TempDir dir("sweep_set_bad");
  try {
    readDoc(dir, doc);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(SweepSet, ReadsTypedSettingsAndViewsWithTheirFallbacks) {
  const test::TempDir dir("sweep_set");
  const SweepSet set = readDoc(dir, validDoc());
  EXPECT_EQ(set.version, "0.1.0");
  EXPECT_EQ(set.settings.spp, 64);
  EXPECT_EQ(set.settings.bounces, 3);
  EXPECT_FALSE(set.settings.radius);
  EXPECT_EQ(set.settings.seed, std::optional<std::uint64_t>(7));
  EXPECT_EQ(set.settings.albedos, (std::vector<double>{0.1, 0.5, 0.9}));
  EXPECT_EQ(set.settings.specular_roughness, (std::vector<double>{0.125, 0.5}));
  EXPECT_EQ(set.settings.specular_spp, 16);
  EXPECT_EQ(set.settings.gbuffer_radii, (std::vector<double>{0.5, 1.0}));
  ASSERT_EQ(set.views.size(), 2u);
  EXPECT_EQ(set.views[0].scene, "room");
  EXPECT_EQ(set.views[0].type, "box");
  EXPECT_EQ(set.views[0].unmasked_pixels, std::optional<std::int64_t>(100));
  // Sweeps before views: the view is its own scene and type, sized by the settings.
  EXPECT_EQ(set.views[1].scene, "b");
  EXPECT_EQ(set.views[1].type, "b");
  EXPECT_EQ(set.views[1].width, 16);
  EXPECT_EQ(set.views[1].height, 8);
  EXPECT_TRUE(set.views[1].camera.is_null());
  EXPECT_EQ(truthChannelSuffix(set, std::nullopt), "");
  EXPECT_EQ(truthChannelSuffix(set, 0.5), "_R0p5");
  EXPECT_EQ(truthChannelSuffix(set, 1.0), "_R1");
}

TEST(SweepSet, WhatTheSweepNeverWritesIsAOneLineError) {
  const auto with = [](const char* key, const json& value) {
    json d = validDoc();
    d["settings"][key] = value;
    return d;
  };
  json twice = validDoc();
  twice["views"][1]["name"] = "a";
  json outside = validDoc();
  outside["views"][1]["file"] = "../b.exr";
  const std::pair<json, std::string> cases[] = {
      {with("specular_spp", 1 << 17), "specular_spp"},  // above what the sweep writes
      {with("albedos", {0.1, 0.1}), "distinct hundredths"},
      {with("albedos", {0.1, 0.105}), "distinct hundredths"},             // a nudged albedo
      {with("specular_roughness", {0.1, 0.104}), "distinct hundredths"},  // one channel name
      {with("specular_roughness", {1.5}), "[0, 1]"},
      {with("gbuffer_radii", {1.0, 0.5}), "ascending"},
      {with("bounces", 0), "bounces"},
      {twice, "listed twice"},
      {outside, "b.exr"},
  };
  for (const auto& [doc, needle] : cases) {
    const std::string what = errorOf(doc);
    EXPECT_NE(what.find(needle), std::string::npos) << needle << ": " << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  const test::TempDir dir("sweep_set_radius");
  const SweepSet set = readDoc(dir, validDoc());
  try {
    truthChannelSuffix(set, 2.0);
    ADD_FAILURE() << "no error for a radius the sweep did not trace";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("0.5"), std::string::npos) << e.what();
  }
}

// A sweep.json of the layout before "views" (its per-view list named "scenes") is refused with
// one line that says to re-run the sweep, never read as an empty or partial set
// (docs/sweep.md "Outputs").
TEST(SweepSet, AnOlderLayoutWithScenesIsRefusedWithOneLineSayingToRerunTheSweep) {
  json old = validDoc();
  old["scenes"] = old["views"];
  old.erase("views");
  const std::string what = errorOf(old);
  EXPECT_NE(what.find("'scenes', an older layout"), std::string::npos) << what;
  EXPECT_NE(what.find("re-run `gtbake sweep`"), std::string::npos) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  json neither = validDoc();
  neither.erase("views");
  EXPECT_NE(errorOf(neither).find("'views' must be a non-empty array"), std::string::npos);
}

}  // namespace
}  // namespace gtbake
