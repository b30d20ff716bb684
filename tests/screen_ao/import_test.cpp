// "Bring your own pass" (docs/screen_ao.md §8): `gtbake gbuffer`'s conventions against a plane of
// known height, its DDS headers against the DDS layout, a built-in estimator imported as an
// engine's pass giving the built-in's verdicts to the bit, and bad imports as one-line errors
// with nothing written.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/image_io.h"
#include "common/output_set.h"
#include "fit/fit_command.h"
#include "gbuffer_scenes.h"
#include "screen_ao/gbuffer_export.h"
#include "screen_ao/screen_ao_command.h"
#include "screen_ao_errors.h"
#include "support/temp_dir.h"
#include "sweep/sweep_command.h"
#include "tune/tiny_sweep.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

Eigen::Matrix4d matrixOf(const json& rows) {
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = rows.at(r).at(c).get<double>();
  }
  return m;
}

std::uint32_t le32(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i)
    v |= static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + i])) << (8 * i);
  return v;
}

float floatAt(const std::string& s, std::size_t at) {
  const std::uint32_t bits = le32(s, at);
  float v = 0.0f;
  std::memcpy(&v, &bits, sizeof(v));
  return v;
}

// The open plane y = 0 (camera 1 m above it, 45° down) swept at 24 × 24 and exported.
fs::path exportOpenPlane(const fs::path& root) {
  const fs::path gltf = root / "open.gltf";
  writeGltfScene(gltf, test::openField());
  SweepOptions s;
  s.scenes = {gltf};
  s.out = root / "sweep";
  s.spp = 4;
  s.width = 24;
  s.height = 24;
  s.specular_roughness = {};
  s.progress = false;
  runSweep(s);
  runGbufferExport({s.out, root / "gbuffer", 0});
  return root / "gbuffer";
}

// Every exported pixel, reconstructed as gbuffer.json says (view point Z·(ndc_x/P00, ndc_y/P11,
// −1), world = V⁻¹·view), lies on the plane y = 0 with the normal +y, and projects back to its
// own pixel centre with a depth in [0, 1].
TEST(GbufferExport, ConventionsReconstructThePlane) {
  test::TempDir dir("gbuffer-plane");
  const fs::path out = exportOpenPlane(dir.path());
  const OutputManifest m = readOutputSet(out, "gbuffer");
  const json doc = json::parse(m.readVerified("gbuffer.json"));
  const json& image = doc["images"][0];
  const Eigen::Matrix4d view = matrixOf(image["view"]);
  const Eigen::Matrix4d proj = matrixOf(image["projection"]);
  const int w = image["width"], h = image["height"];
  const ExrImage exr = decodeExr(m.readVerified(image["exr"]), "exr");
  std::size_t seen = 0;
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * w + i;
      if (exr.channels.at("mask")[p] == 0.0f) continue;
      ++seen;
      const double z = exr.channels.at("depth")[p];
      const double nx = 2.0 * (i + 0.5) / w - 1.0, ny = 1.0 - 2.0 * (j + 0.5) / h;
      const Eigen::Vector4d v(z * nx / proj(0, 0), z * ny / proj(1, 1), -z, 1.0);
      const Eigen::Vector4d world = view.inverse() * v;
      EXPECT_NEAR(world.y(), 0.0, 2e-6 * z) << i << " " << j;
      const Eigen::Vector3d n(exr.channels.at("normal.X")[p], exr.channels.at("normal.Y")[p],
                              exr.channels.at("normal.Z")[p]);
      const Eigen::Vector3d n_world = view.topLeftCorner<3, 3>().transpose() * n;
      EXPECT_NEAR(n_world.y(), 1.0, 1e-6);
      const Eigen::Vector4d clip = proj * v;
      EXPECT_NEAR(clip.x() / clip.w(), nx, 1e-6);
      EXPECT_NEAR(clip.y() / clip.w(), ny, 1e-6);
      EXPECT_GT(clip.z() / clip.w(), 0.0);
      EXPECT_LT(clip.z() / clip.w(), 1.0);
    }
  }
  EXPECT_GT(seen, static_cast<std::size_t>(w * h / 2));
  // The projection's depth range: near -> 0, far -> 1.
  const Eigen::Vector4d near = proj * Eigen::Vector4d(0, 0, -kExportNear, 1);
  const Eigen::Vector4d far = proj * Eigen::Vector4d(0, 0, -kExportFar, 1);
  EXPECT_NEAR(near.z() / near.w(), 0.0, 1e-12);
  EXPECT_NEAR(far.z() / far.w(), 1.0, 1e-12);
}

// The DDS files by the Microsoft layout (DDS_HEADER at 4, DDS_HEADER_DXT10 at 128, data at 148):
// R32_FLOAT depth and R32G32B32A32_FLOAT normal + mask, the EXR's floats to the bit.
TEST(GbufferExport, DdsFilesHoldTheExrFloats) {
  test::TempDir dir("gbuffer-dds");
  const fs::path out = exportOpenPlane(dir.path());
  const OutputManifest m = readOutputSet(out, "gbuffer");
  const ExrImage exr = decodeExr(m.readVerified("open.exr"), "exr");
  const std::string depth = m.readVerified("open.depth.dds");
  const std::string normal = m.readVerified("open.normal.dds");
  EXPECT_EQ(depth.substr(0, 4), "DDS ");
  for (const std::string* dds : {&depth, &normal}) {
    EXPECT_EQ(le32(*dds, 12), 24u);          // dwHeight
    EXPECT_EQ(le32(*dds, 16), 24u);          // dwWidth
    EXPECT_EQ(le32(*dds, 84), 0x30315844u);  // "DX10"
    EXPECT_EQ(le32(*dds, 132), 3u);          // TEXTURE2D
    EXPECT_EQ(le32(*dds, 140), 1u);          // arraySize
  }
  EXPECT_EQ(le32(depth, 128), 41u);  // DXGI_FORMAT_R32_FLOAT
  EXPECT_EQ(le32(normal, 128), 2u);  // DXGI_FORMAT_R32G32B32A32_FLOAT
  EXPECT_EQ(le32(depth, 20), 24u * 4);
  EXPECT_EQ(le32(normal, 20), 24u * 16);
  ASSERT_EQ(depth.size(), 148u + 24 * 24 * 4);
  ASSERT_EQ(normal.size(), 148u + 24 * 24 * 16);
  const char* names[4] = {"normal.X", "normal.Y", "normal.Z", "mask"};
  for (std::size_t p = 0; p < 24 * 24; ++p) {
    EXPECT_EQ(floatAt(depth, 148 + 4 * p), exr.channels.at("depth")[p]);
    for (int c = 0; c < 4; ++c) {
      EXPECT_EQ(floatAt(normal, 148 + 16 * p + 4 * c), exr.channels.at(names[c])[p]);
    }
  }
}

// A tiny sweep of four classic scenes, hbao's screen-ao set on it, the G-buffer export, and hbao's
// Â and b̂ written as an engine's pass would write them: <image>.exr of gbuffer.json's images with
// channels A and BNX BNY BNZ.
struct RoundTrip {
  fs::path root, sweep, builtin, user;
};

const RoundTrip& roundTrip() {
  static const test::TempDir dir("gbuffer-round-trip");
  static const RoundTrip r = [] {
    RoundTrip t;
    t.root = dir.path();
    t.sweep = test::tinySweep(t.root / "sweep", {"cavity", "clutter", "corner", "spheres"});
    ScreenAoOptions s;
    s.sweep = t.sweep;
    s.out = t.builtin = t.root / "builtin";
    s.estimators = {Estimator::kHbao};
    s.progress = false;
    runScreenAo(s);
    runGbufferExport({t.sweep, t.root / "gbuffer", 0});
    const OutputManifest g = readOutputSet(t.root / "gbuffer", "gbuffer");
    const OutputManifest b = readOutputSet(t.builtin, "screen_ao");
    t.user = t.root / "user";
    fs::create_directories(t.user);
    const json doc = json::parse(g.readVerified("gbuffer.json"));
    for (const json& image : doc["images"]) {
      const std::string file = image["exr"];
      const ExrImage exr = decodeExr(b.readVerified(file), file);
      writeExr(t.user / file, exr.width, exr.height,
               {{"A", exr.channels.at("hbao.A")},
                {"BNX", exr.channels.at("hbao.BNX")},
                {"BNY", exr.channels.at("hbao.BNY")},
                {"BNZ", exr.channels.at("hbao.BNZ")}});
    }
    return t;
  }();
  return r;
}

ScreenAoOptions importOptions(const fs::path& out, const fs::path& user, double radius) {
  ScreenAoOptions o;
  o.sweep = roundTrip().sweep;
  o.out = out;
  o.estimators = {Estimator::kHbao};
  o.imports = {{"my-pass", user, radius}};
  o.progress = false;
  return o;
}

json fitJson(const fs::path& screen_ao, const std::string& estimator, const fs::path& out) {
  FitOptions f;
  f.sweep = roundTrip().sweep;
  f.out = out;
  f.write_report = false;
  f.print_summary = false;
  f.progress = false;
  f.input = {estimator, screen_ao};
  runFit(f);
  json doc = json::parse(test::readBytes(out));
  doc.erase("input");  // names the estimator
  return doc;
}

// The imported copy of hbao gives hbao's statistics, EXR channels and profile fit to the bit.
TEST(ScreenAoImport, BuiltInEstimatorRoundTripsBitForBit) {
  const RoundTrip& r = roundTrip();
  const fs::path out = r.root / "both";
  runScreenAo(importOptions(out, r.user, 1.0));
  const OutputManifest m = readOutputSet(out, "screen_ao");
  const json doc = json::parse(m.readVerified("screen_ao.json"));
  const json& mine = doc["estimators"]["my-pass"];
  const json& hbao = doc["estimators"]["hbao"];
  EXPECT_EQ(mine["scenes"].dump(), hbao["scenes"].dump());
  EXPECT_EQ(mine["radius_channel"], "A_R1");
  EXPECT_EQ(mine["radius_channel"], hbao["radius_channel"]);
  const json alone = json::parse(test::readBytes(r.builtin / "screen_ao.json"));
  EXPECT_EQ(alone["estimators"]["hbao"]["scenes"].dump(), hbao["scenes"].dump());
  for (const json& image : doc["images"]) {
    const ExrImage exr = decodeExr(m.readVerified(image["file"]), "exr");
    for (const char* c : {".A", ".BNX", ".BNY", ".BNZ"}) {
      EXPECT_EQ(exr.channels.at(std::string("my-pass") + c),
                exr.channels.at(std::string("hbao") + c));
    }
  }
  EXPECT_EQ(fitJson(out, "my-pass", r.root / "fit_mine.json").dump(),
            fitJson(out, "hbao", r.root / "fit_hbao.json").dump());
}

// b̂ given in view space (VBNX VBNY VBNZ = the view matrix of gbuffer.json times the world b̂)
// scores as the world-space b̂ up to float rounding; Â to the bit. No built-in estimator runs.
TEST(ScreenAoImport, ViewSpaceBentNormalsMatchWorldSpace) {
  const RoundTrip& r = roundTrip();
  const fs::path view_dir = r.root / "user_view";
  fs::create_directories(view_dir);
  const json gbuffer = json::parse(test::readBytes(r.root / "gbuffer" / "gbuffer.json"));
  for (const json& image : gbuffer["images"]) {
    const std::string file = image["exr"];
    const ExrImage exr = readExr(r.user / file);
    const Eigen::Matrix3d rotation = matrixOf(image["view"]).topLeftCorner<3, 3>();
    std::vector<ExrChannel> channels = {
        {"A", exr.channels.at("A")}, {"VBNX", {}}, {"VBNY", {}}, {"VBNZ", {}}};
    for (std::size_t p = 0; p < exr.channels.at("A").size(); ++p) {
      const Eigen::Vector3d world(exr.channels.at("BNX")[p], exr.channels.at("BNY")[p],
                                  exr.channels.at("BNZ")[p]);
      const Eigen::Vector3d view = rotation * world;
      for (int c = 0; c < 3; ++c) channels[1 + c].pixels.push_back(static_cast<float>(view[c]));
    }
    writeExr(view_dir / file, exr.width, exr.height, channels);
  }
  ScreenAoOptions o = importOptions(r.root / "view", r.user, 1.0);
  o.estimators = {};
  o.imports.push_back({"my-view", view_dir, 1.0});
  runScreenAo(o);
  const json doc = json::parse(test::readBytes(o.out / "screen_ao.json"));
  ASSERT_EQ(doc["estimators"].size(), 2u);
  const json& world = doc["estimators"]["my-pass"]["scenes"]["all"]["all"];
  const json& view = doc["estimators"]["my-view"]["scenes"]["all"]["all"];
  for (const char* key : {"pixels", "bias", "rmse", "bias_at_radius", "rmse_at_radius"}) {
    EXPECT_EQ(world[key], view[key]) << key;
  }
  EXPECT_NEAR(world["bent_mean_deg"].get<double>(), view["bent_mean_deg"].get<double>(), 1e-4);
  EXPECT_NEAR(world["bent_p95_deg"].get<double>(), view["bent_p95_deg"].get<double>(), 1e-4);
  EXPECT_GT(world["bent_mean_deg"].get<double>(), 1.0);  // the comparison is not of zeros
}

// A copy of the user's images with cavity's A (or the whole file) replaced.
fs::path editedImages(const std::string& tag, float value, int side = 0) {
  const RoundTrip& r = roundTrip();
  const fs::path dir = r.root / ("user_" + tag);
  fs::create_directories(dir);
  for (const auto& entry : fs::directory_iterator(r.user)) {
    fs::copy_file(entry.path(), dir / entry.path().filename(),
                  fs::copy_options::overwrite_existing);
  }
  ExrImage exr = readExr(dir / "cavity.exr");
  const std::vector<float>& mask =
      decodeExr(test::readBytes(r.builtin / "cavity.exr"), "cavity").channels.at("mask");
  std::size_t p = 0;
  while (mask[p] == 0.0f) ++p;  // the first unmasked pixel
  exr.channels["A"][p] = value;
  if (side > 0) {
    writeExr(dir / "cavity.exr", side, side, {{"A", std::vector<float>(side * side, 0.5f)}});
  } else {
    std::vector<ExrChannel> channels;
    for (const auto& [name, values] : exr.channels) channels.push_back({name, values});
    writeExr(dir / "cavity.exr", exr.width, exr.height, channels);
  }
  return dir;
}

TEST(ScreenAoImport, BadImportsAreOneLineErrors) {
  const RoundTrip& r = roundTrip();
  const fs::path out = r.root / "bad";
  test::expectScreenAoError(importOptions(out, editedImages("size", 0.5f, 8), 1.0), "size 8x8");
  test::expectScreenAoError(importOptions(out, editedImages("nan", std::nanf("")), 1.0),
                            "not in [0, 1]");
  test::expectScreenAoError(importOptions(out, editedImages("high", 1.0001f), 1.0),
                            "not in [0, 1]");
  test::expectScreenAoError(importOptions(out, editedImages("low", -1e-6f), 1.0), "not in [0, 1]");
  const fs::path missing = editedImages("missing", 0.5f);
  fs::remove(missing / "spheres.exr");
  test::expectScreenAoError(importOptions(out, missing, 1.0), "no image");
  test::expectScreenAoError(importOptions(out, r.user, 0.7), "A_R0p7");
  ScreenAoOptions twice = importOptions(out, r.user, 1.0);
  twice.imports.push_back(twice.imports.front());
  test::expectScreenAoError(twice, "imported twice");
  ScreenAoOptions collide = importOptions(out, r.user, 1.0);
  collide.imports.front().name = "hbao";
  test::expectScreenAoError(collide, "built-in");
  for (const char* text : {"hbao=dir", "all=dir", "My Pass=dir", "mine", "mine=", "mine=d:radius=0",
                           "mine=d:radius=x", ".hidden=d"}) {
    EXPECT_THROW(parseImport(text), Error) << text;
  }
  const ImportedEstimator e = parseImport("mine=/a:b/dir:radius=0.5");
  EXPECT_EQ(e.name, "mine");
  EXPECT_EQ(e.dir, fs::path("/a:b/dir"));
  EXPECT_EQ(e.radius, 0.5);
  EXPECT_TRUE(isEstimatorName("mine"));
  EXPECT_TRUE(isEstimatorName("hbao"));
  EXPECT_FALSE(isEstimatorName("all"));
  EXPECT_FALSE(isEstimatorName("a.b"));
}

}  // namespace
}  // namespace gtbake
