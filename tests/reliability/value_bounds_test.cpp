// Values checked where they are read, even under a consistent (resealed) manifest
// (docs/limits.md §Values): escape probabilities and S in [0, 1], bounded sizes and shard
// counts, roughness lists that match what was traced, constants that print as finite floats, and
// a generated header that compiles after hostile and fuzzed inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>

#include "common/image_io.h"
#include "fit/sweep_data.h"
#include "reliability_fixtures.h"
#include "screen_ao/gbuffer.h"
#include "sweep/shard_manifest.h"
#include "validate_gtso/specular_sweep.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::ExportFixture;
using test::readBytes;
using test::spit;
using test::SweepFixture;
using test::TempDir;

const SweepFixture& fixture() {
  static const SweepFixture f;
  return f;
}

// Sets pixel 0 of `channel` in `exr` (a file of the sweep in `dir`) and reseals the sweep.
void editPixel(const fs::path& dir, const std::string& exr, const std::string& channel, float v) {
  ExrImage image = decodeExr(readBytes(dir / exr), exr);
  std::vector<ExrChannel> channels;
  for (auto& [name, pixels] : image.channels) {
    if (name == channel) pixels[0] = v;
    channels.push_back({name, pixels});
  }
  spit(dir / exr, encodeExr(image.width, image.height, channels, image.attributes));
  resealOutputSet(dir, "sweep");
}

void editJson(const fs::path& dir, const std::string& name, const std::string& set,
              const std::function<void(json&)>& edit) {
  json doc = json::parse(readBytes(dir / name));
  edit(doc);
  spit(dir / name, doc.dump());
  resealOutputSet(dir, set);
}

TEST(ValueBounds, FitRefusesProbabilitiesOutsideTheirRange) {
  TempDir dir("bounds_fit");
  const fs::path sweep = dir.path() / "s";
  runSweep(fixture().options(sweep));
  const std::string exr = readBytes(sweep / "box_b.exr");
  editPixel(sweep, "box_b.exr", "A", 1.5f);
  EXPECT_ERROR(loadSweep(sweep), "outside [0, 1]");
  spit(sweep / "box_b.exr", exr);
  editPixel(sweep, "box_b.exr", "H0.P1", -0.25f);
  EXPECT_ERROR(loadSweep(sweep), "outside [0, 1]");
  spit(sweep / "box_b.exr", exr);
  editPixel(sweep, "box_b.exr", "A", 0.6f);
  editPixel(sweep, "box_b.exr", "P1", 0.6f);
  EXPECT_ERROR(loadSweep(sweep), "above 1");
}

TEST(ValueBounds, ScreenAoRefusesTruthOutsideItsRange) {
  TempDir dir("bounds_screen_ao");
  const fs::path sweep = dir.path() / "s";
  runSweep(fixture().options(sweep));
  EXPECT_EQ(readSweepImages(sweep).images.size(), 2u);
  editPixel(sweep, "box_b.exr", "A", -0.5f);
  EXPECT_ERROR(readSweepImages(sweep), "A or A_R outside [0, 1]");
}

TEST(ValueBounds, FitRefusesAlbedoListsItWasNotTracedWith) {
  TempDir dir("bounds_albedos");
  const fs::path sweep = dir.path() / "s";
  runSweep(fixture().options(sweep));
  const std::string good = readBytes(sweep / "sweep.json");
  for (const json& list : {json{0.1, 0.2, 0.3, 0.4, 0.5000001, 0.7, 0.9},
                           json{0.1, 0.2, 0.3, 0.4, 0.5, 0.5, 0.7, 0.9}}) {
    editJson(sweep, "sweep.json", "sweep", [&](json& d) { d["settings"]["albedos"] = list; });
    EXPECT_ERROR(loadSweep(sweep), "albedos must be distinct hundredths");
    spit(sweep / "sweep.json", good);
  }
}

TEST(ValueBounds, SweepAndShardSizesAreBounded) {
  TempDir dir("bounds_sizes");
  const fs::path sweep = dir.path() / "s";
  runSweep(fixture().options(sweep));
  editJson(sweep, "sweep.json", "sweep", [](json& d) { d["views"][0]["width"] = 1000000; });
  EXPECT_ERROR(loadSweep(sweep), "'width' must be an integer in [1, 8192]");
  SweepOptions o = fixture().options(dir.path() / "shard");
  o.shards = 2;
  runSweep(o);
  const fs::path shard = o.out;
  const std::string good = readBytes(shard / "shard.json");
  editJson(shard, "shard.json", kShardSet, [](json& d) { d["shards"] = 2147483648ll; });
  EXPECT_ERROR(readShardManifest(shard), "'shards' must be an integer in [1, 65536]");
  spit(shard / "shard.json", good);
  editJson(shard, "shard.json", kShardSet, [](json& d) { d["width"] = 1000000; });
  EXPECT_ERROR(readShardManifest(shard), "'width' must be an integer");
  spit(shard / "shard.json", good);
  editJson(shard, "shard.json", kShardSet, [](json& d) { d["seconds"] = -1; });
  EXPECT_ERROR(readShardManifest(shard), "'seconds' must be a finite number");
}

TEST(ValueBounds, ValidateGtsoRefusesRoughnessListsItWasNotTracedWith) {
  TempDir dir("bounds_roughness");
  SweepOptions o = fixture().options(dir.path() / "s", 1, 16);
  o.specular_roughness = {0.1, 0.4};
  o.specular_spp = 2;
  runSweep(o);
  const fs::path sweep = o.out;
  EXPECT_EQ(readSpecularSweep(sweep).roughness.size(), 2u);
  const std::string good = readBytes(sweep / "sweep.json");
  const std::string exr = readBytes(sweep / "box_b.exr");
  const std::vector<std::pair<json, std::string>> lists = {
      {{0.1, 0.1}, "distinct hundredths"},              // duplicated
      {{0.1000001, 0.4}, "gtbake.specular_roughness"},  // nudged: the same channel names
      {{0.1, 1.5}, "[0, 1]"},
      {json::array(), "no specular channels"}};
  for (const auto& [list, fragment] : lists) {
    editJson(sweep, "sweep.json", "sweep",
             [&](json& d) { d["settings"]["specular_roughness"] = list; });
    EXPECT_ERROR(readSpecularSweep(sweep), fragment);
    spit(sweep / "sweep.json", good);
  }
  editPixel(sweep, "box_b.exr", "S040", 1.5f);
  EXPECT_ERROR(readSpecularSweep(sweep), "S estimate outside [0, 1]");
  spit(sweep / "box_b.exr", exr);
  editPixel(sweep, "box_b.exr", "A", -0.5f);
  EXPECT_ERROR(readSpecularSweep(sweep), "A outside [0, 1]");
}

// The fixture's fit.json / gtso.json edited (resealed) and exported; returns the error ("" when
// export succeeded).
struct ExportEdits {
  ExportFixture f;
  fs::path out = f.root.path() / "export";
  ExportEdits() { f.encode(out); }
  std::string exportWith(const std::function<void(json&)>& fit,
                         const std::function<void(json&)>& gtso) {
    const std::string fit_bytes = readBytes(f.fit);
    const std::string gtso_bytes = readBytes(f.gtso / "gtso.json");
    editJson(f.fit.parent_path(), "fit.json", "fit", fit);
    editJson(f.gtso, "gtso.json", "gtso", gtso);
    const std::string error = test::errorOf([&] { runExport(f.options(out)); });
    spit(f.fit, fit_bytes);
    spit(f.gtso / "gtso.json", gtso_bytes);
    resealOutputSet(f.fit.parent_path(), "fit");
    resealOutputSet(f.gtso, "gtso");
    return error;
  }
  // g++ -fsyntax-only of the header just exported, included by a consumer.
  bool headerCompiles() const {
    std::ofstream(out / "consumer.cpp") << "#include \"gtbake_tables.h\"\n"
                                        << "float f() { return gtbake::kConeApertureU; }\n";
    const std::string cmd = std::string(GTBAKE_TEST_CXX) +
                            " -std=c++17 -fsyntax-only -Wall -Wextra -Wpedantic -Werror -I" +
                            out.string() + " " + (out / "consumer.cpp").string() + " 2>&1";
    return std::system(cmd.c_str()) == 0;
  }
};

void noEdit(json&) {}

TEST(ValueBounds, ExportRefusesConstantsThatAreNotFiniteFloats) {
  ExportEdits e;
  EXPECT_NE(e.exportWith([](json& d) { d["linear"]["a1"] = 1e39; }, noEdit)
                .find("'a1' must be a finite number in"),
            std::string::npos);
  EXPECT_NE(e.exportWith([](json& d) { d["linear_se"]["c0"] = -1e300; }, noEdit)
                .find("'c0' must be a finite number in [0,"),
            std::string::npos);
  EXPECT_NE(e.exportWith(noEdit, [](json& d) { d["cone"]["u_se"] = 1e39; }).find("'u_se'"),
            std::string::npos);
  EXPECT_NE(e.exportWith(noEdit, [](json& d) { d["closed_form"]["coefficients"][3] = -1e300; })
                .find("closed_form.coefficients"),
            std::string::npos);
  // A layout axis that get<int>() would wrap to 0.
  const std::string encode = readBytes(e.out / "encode.json");
  editJson(e.out, "encode.json", "encode",
           [](json& d) { d["layouts"]["3d"]["chosen"]["axis"][0] = 4294967296ll; });
  EXPECT_NE(e.exportWith(noEdit, noEdit).find("not three table axes"), std::string::npos);
  // The 4D tiles across x (docs/export.md §2c): an integer in [1, N_w], not wrapped either.
  for (const json& bad : {json(4294967296ll), json(0), json(1.5), json("4")}) {
    spit(e.out / "encode.json", encode);
    editJson(e.out, "encode.json", "encode",
             [&](json& d) { d["layouts"]["4d"]["packing"]["tiles_x"] = bad; });
    EXPECT_NE(e.exportWith(noEdit, noEdit).find("no valid layouts/4d/packing/tiles_x"),
              std::string::npos)
        << bad;
  }
  spit(e.out / "encode.json", encode);
  resealOutputSet(e.out, "encode");
  // A table name that would end the comment it is quoted in and inject code.
  EXPECT_NE(
      e.exportWith(noEdit,
                   [](json& d) { d["tables"]["3d"]["file"] = "gtso3d.f32\n#error injected\n//\\"; })
          .find("plain file name"),
      std::string::npos);
}

// Every constant at a random point of its documented range (magnitudes from 1e-45 to 1e6, both
// signs, subnormal floats and values that round to zero included): the header always compiles.
TEST(ValueBounds, GeneratedHeaderCompilesAcrossTheBounds) {
  ExportEdits e;
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> exponent(-45.0, 6.0);
  auto value = [&](bool non_negative) {
    const double v = std::pow(10.0, exponent(rng));
    return non_negative || rng() % 2 == 0 ? v : -v;
  };
  const char* names[6] = {"a1", "a0", "b1", "b0", "c1", "c0"};
  for (int round = 0; round < 3; ++round) {
    const std::string error = e.exportWith(
        [&](json& d) {
          for (const char* n : names) {
            d["linear"][n] = std::min(value(false), 1e6);
            d["linear_se"][n] = std::min(value(true), 1e6);
          }
        },
        [&](json& d) {
          d["cone"]["u"] = std::min(value(true), 0.999);
          d["cone"]["u_se"] = std::min(value(true), 1e6);
          for (auto& c : d["closed_form"]["coefficients"]) c = std::min(value(false), 1e6);
          // Strings the provenance comments quote: none may end the comment or splice a line.
          d["roughness_convention"] = "r_p\\";
          d["texel_rule"] = "a\r#error injected\r\\";
          d["cone"]["convention"] = "*/ ?\?/ \u2028 \\";
        });
    EXPECT_EQ(error, "");
    EXPECT_TRUE(e.headerCompiles()) << "round " << round;
  }
}

}  // namespace
}  // namespace gtbake
