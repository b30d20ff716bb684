// Hostile inputs to the readers added after the first reliability pass (docs/limits.md "Testing
// the readers"), each also a fuzz target: a screen-ao set (fit and validate-gtso --estimator),
// export's engine profiles and tuned settings, tune's --grid and screen-ao's --setting, and the
// corpus descriptions. Each must be a one-line gtbake::Error (or the right result).
#include <gtest/gtest.h>

#include <chrono>
#include <nlohmann/json.hpp>

#include "common/image_io.h"
#include "common/output_set.h"
#include "fit/fit_set.h"
#include "fit/screen_estimate.h"
#include "reliability_fixtures.h"
#include "scene/scene_corpus.h"
#include "screen_ao/screen_ao_settings.h"
#include "tune/tune_grid.h"
#include "tune/tune_set.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::spit;
using test::TempDir;

// Writes `doc` as dir/name and seals it as the set `command`.
void sealed(const fs::path& dir, const std::string& command, const std::string& name,
            const std::string& doc) {
  fs::create_directories(dir);
  spit(dir / name, doc);
  sealOutputSet(dir, command, {name});
}

TEST(LaterReaders, ScreenAoSetValuesAndNamesAreChecked) {
  TempDir dir("later_screen_ao");
  const fs::path set = dir.path() / "screen_ao";
  fs::create_directories(set);
  const std::vector<float> mask = {1, 1, 0, 1}, bn = {0, 0, 0, 0}, one = {1, 1, 1, 1};
  auto write = [&](const std::vector<float>& a, const std::vector<float>& z, const json& doc) {
    spit(set / "a.exr",
         encodeExr(2, 2, {{"mask", mask}, {"e.A", a}, {"e.BNX", bn}, {"e.BNY", bn}, {"e.BNZ", z}}));
    spit(set / "screen_ao.json", doc.dump());
    sealOutputSet(set, "screen_ao", {"screen_ao.json", "a.exr"});
  };
  const json good = {{"estimators", {{"e", json::object()}}},
                     {"images", {{{"name", "a"}, {"file", "a.exr"}}}}};
  write({0, 0.5f, 7, 1}, one, good);  // masked pixels may hold anything
  EXPECT_EQ(ScreenEstimateSet({"e", set}).read("a", dir.path(), true).A[1], 0.5f);
  EXPECT_ERROR(ScreenEstimateSet({"other", set}), "has no estimator 'other'");
  EXPECT_ERROR(ScreenEstimateSet({"e", set}).read("b", dir.path(), true), "has no image 'b'");
  write({0, 1.5f, 0, 1}, one, good);
  EXPECT_ERROR(ScreenEstimateSet({"e", set}).read("a", dir.path(), false), "outside [0, 1]");
  write({0, 0, 0, 0}, {1, 2, 1, 1}, good);
  EXPECT_ERROR(ScreenEstimateSet({"e", set}).read("a", dir.path(), true), "not a unit vector");
  json twice = good;  // one name listed twice: refused, not the last one kept
  twice["images"].push_back({{"name", "a"}, {"file", "a.exr"}});
  write({0, 0.5f, 0, 1}, one, twice);
  EXPECT_ERROR(ScreenEstimateSet({"e", set}), "image 'a' is listed twice");
  json outside = good;
  outside["images"][0]["file"] = "../a.exr";
  write({0, 0, 0, 0}, one, outside);
  EXPECT_ERROR(ScreenEstimateSet({"e", set}).read("a", dir.path(), true), "'..' is not allowed");
  write({0, 0, 0, 0}, one, {{"images", json::array()}});
  EXPECT_ERROR(ScreenEstimateSet({"e", set}), "needs 'images' and 'estimators'");
}

json profileJson(const std::string& estimator) {
  json doc;
  for (const char* c : {"a1", "a0", "b1", "b0", "c1", "c0"}) {
    doc["linear"][c] = 0.5;
    doc["linear_se"][c] = 0.01;
  }
  doc["input"] = {{"estimator", estimator}};
  doc["errors"] = {{"shipped", {{"rmse", 0.03}}}, {"held_out_by_scene", {{"rmse", 0.04}}}};
  doc["scene_jackknife"] = {{"band_max", {{"value", 0.02}}}};
  return doc;
}

TEST(LaterReaders, ProfilesAreNamedAndBounded) {
  TempDir dir("later_profiles");
  const fs::path root = dir.path() / "profiles";
  sealed(root / "hbao", "fit", "fit.json", profileJson("hbao").dump());
  ASSERT_EQ(readProfiles(root).size(), 1u);
  sealed(root / "hbao", "fit", "fit.json", profileJson("gtao-runtime").dump());
  EXPECT_ERROR(readProfiles(root), "not the profile of estimator 'hbao'");
  json huge = profileJson("hbao");
  huge["linear"]["a1"] = 1e39;  // would print as inff in the header
  sealed(root / "hbao", "fit", "fit.json", huge.dump());
  EXPECT_ERROR(readProfiles(root), "'a1' must be a finite number in");
  json negative = profileJson("hbao");
  negative["errors"]["shipped"]["rmse"] = -1;
  sealed(root / "hbao", "fit", "fit.json", negative.dump());
  EXPECT_ERROR(readProfiles(root), "'rmse' must be a finite number in [0,");
  sealed(root / "hbao", "fit", "fit.json", profileJson("hbao").dump());
  sealed(root / "Bad_Name", "fit", "fit.json", profileJson("Bad_Name").dump());
  EXPECT_ERROR(readProfiles(root), "lower-case letters, digits and '-'");
}

json tunedJson() {
  const json refit = {{"a1", 0.5}, {"a0", 1.25}, {"b1", 0.75},
                      {"b0", 1.5}, {"c1", 0.25}, {"c0", 1}};
  const json profile = {{"value", 2.5},
                        {"interval", {2.0, 3.0}},
                        {"at_bound", false},
                        {"grid_best", {{"value", 2.0}, {"profile_held_out", 0.125}}},
                        {"refit", refit}};
  return {{"results",
           {{"gtao-runtime",
             {{"radius",
               {{"default", 1.0},
                {"optimum", {{"paper", {{"value", 4.0}}}, {"profile", profile}}}}}}}}}};
}

TEST(LaterReaders, TunedSettingsGridsAndSettingsAreChecked) {
  TempDir dir("later_tune");
  const fs::path file = dir.path() / "tune" / "tune.json";
  sealed(file.parent_path(), "tune", "tune.json", tunedJson().dump());
  ASSERT_EQ(readTunedSettings(file).size(), 1u);
  json bad = tunedJson();
  bad["results"]["gtao-runtime"]["radius"]["optimum"]["profile"]["interval"] = {1.0};
  sealed(file.parent_path(), "tune", "tune.json", bad.dump());
  EXPECT_ERROR(readTunedSettings(file), "interval must be [low, high]");
  bad = tunedJson();
  bad["results"]["GTAO\nX"] = bad["results"]["gtao-runtime"];
  sealed(file.parent_path(), "tune", "tune.json", bad.dump());
  EXPECT_ERROR(readTunedSettings(file), "is not an estimator's settings");
  bad = tunedJson();
  bad["results"]["gtao-runtime"]["radius"]["default"] = "1";
  sealed(file.parent_path(), "tune", "tune.json", bad.dump());
  EXPECT_ERROR(readTunedSettings(file), "'default' must be a finite number");
  // tune --grid and screen-ao --setting text: non-finite, repeated and unknown values.
  std::vector<SettingGrid> grids = defaultGrids(tunedEstimators());
  for (const char* text :
       {"gtao-runtime.radius=1,1e999", "gtao-runtime.radius=1,nan", "gtao-runtime.radius=1,1",
        "gtao-runtime.nope=1,2", "x.radius=1,2", "gtao-runtime.radius="}) {
    EXPECT_NE(test::errorOf([&] { applyGridOption(&grids, text); }), "") << text;
  }
  ScreenAoSettings settings;
  for (const char* text : {"hbao.radius=inf", "hbao.radius=-1", "all.radius=1e400"}) {
    EXPECT_NE(test::errorOf([&] {
                applySetting(&settings, text);
                validateSettings(settings);
              }),
              "")
        << text;
  }
  EXPECT_ERROR(parseEstimatorList("hbao,hbao"), "hbao");
}

// A description is (type, variant, seed): unknown types and negative variants are one-line
// errors; cavity_1 of seed 4504699138998537, whose graded ground rounded a hair short of its
// extent, added rings until memory ran out and now takes milliseconds.
TEST(LaterReaders, CorpusDescriptionsAreRefusedOrBuilt) {
  EXPECT_ERROR(makeCorpusScene("caves", 0, 1), "unknown scene type 'caves'");
  EXPECT_ERROR(makeCorpusScene("rocks", -1, 1), "a scene variant must be 0 or more");
  const auto start = std::chrono::steady_clock::now();
  const Scene cavity = makeCorpusScene("cavity", 1, 4504699138998537ull);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  EXPECT_EQ(cavity.name, "cavity_1");
  EXPECT_LT(cavity.triangles.size(), 100000u);
  const Scene far = makeCorpusScene("mechanical", 2147483647, 18446744073709551615ull);
  EXPECT_EQ(far.name, "mechanical_2147483647");
  EXPECT_FALSE(far.triangles.empty());
}

}  // namespace
}  // namespace gtbake
