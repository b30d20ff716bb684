// runSweep end to end: glTF in, EXR/PNG/JSON out (docs/index.md "Pipeline"). Determinism across
// thread counts, the channel layout, a closed form seen through the camera's pixels, and bad input.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>

#include <Eigen/Core>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/image_io.h"
#include "scene/auto_camera.h"
#include "scene/procedural_scenes.h"
#include "scene/scene.h"
#include "support/test_scenes.h"
#include "sweep/camera_json.h"
#include "sweep/embree_tracer.h"
#include "sweep/sweep_command.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

class SweepCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("gtbake_test_sweep_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "scenes");
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path writeScene(const Scene& scene, const std::string& name) {
    const fs::path path = root_ / "scenes" / (name + ".gltf");
    writeGltfScene(path, scene);
    return path;
  }

  SweepOptions options(const fs::path& scene, const std::string& out) const {
    SweepOptions o;
    o.scenes = {scene};
    o.out = root_ / out;
    o.spp = 16;
    o.width = 40;
    o.height = 30;
    o.progress = false;
    return o;
  }

  // Runs the sweep, expects a one-line gtbake::Error and no output directory.
  void expectRejected(const SweepOptions& o, const std::string& fragment) {
    try {
      runSweep(o);
      ADD_FAILURE() << "accepted bad input (" << fragment << ")";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(fragment), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
    EXPECT_FALSE(fs::exists(o.out)) << "output left behind for: " << fragment;
  }

  fs::path root_;
};

TEST_F(SweepCommand, SameSeedSameBytesOnOneAndTwoThreads) {
  const fs::path scene = writeScene(makeSphereOnPlaneScene(1.0), "spheres");
  SweepOptions one = options(scene, "one");
  one.threads = 1;
  SweepOptions two = options(scene, "two");
  two.threads = 2;
  runSweep(one);
  runSweep(two);
  const std::string a = readFile(one.out / "spheres.exr");
  const std::string b = readFile(two.out / "spheres.exr");
  ASSERT_GT(a.size(), 0u);
  EXPECT_TRUE(a == b) << "EXR bytes differ between 1 and 2 threads";
  EXPECT_EQ(readFile(one.out / "spheres_A.png"), readFile(two.out / "spheres_A.png"));

  SweepOptions other_seed = options(scene, "seed2");
  other_seed.seed = 2;
  runSweep(other_seed);
  EXPECT_FALSE(a == readFile(other_seed.out / "spheres.exr")) << "the seed changes nothing";
}

TEST_F(SweepCommand, ChannelsJsonAndHalves) {
  const fs::path scene = writeScene(makeSphereOnPlaneScene(1.0), "spheres");
  SweepOptions o = options(scene, "out");
  o.bounces = 2;
  const SweepResult result = runSweep(o);
  ASSERT_EQ(result.views.size(), 1u);
  const ExrImage image = readExr(o.out / "spheres.exr");
  std::vector<std::string> names;
  for (const auto& [name, pixels] : image.channels) names.push_back(name);
  std::vector<std::string> expected = {"A", "A_R1", "BNX", "BNY", "BNZ"};
  for (const char* g : {"G010", "G020", "G030", "G040", "G050", "G070", "G090"}) {
    expected.push_back(g);
  }
  for (const char* h : {"H0.", "H1."}) {
    for (const char* c : {"A", "P1", "P2", "S010", "S025", "S040", "S060", "S080"}) {
      expected.push_back(h + std::string(c));
    }
  }
  for (const char* c : {"NX", "NY", "NZ", "P1", "P2", "S010", "S025", "S040", "S060", "S080", "VX",
                        "VY", "VZ", "Z", "mask"}) {
    expected.push_back(c);
  }
  // The near-field channels of the default G-buffer radius 1 (docs/sweep.md, "Near-field truth").
  for (const char* c : {"P1", "P2", "G010", "G020", "G030", "G040", "G050", "G070", "G090", "S010",
                        "S025", "S040", "S060", "S080"}) {
    expected.push_back(std::string(c) + "_R1");
  }
  for (const char* h : {"H0.", "H1."}) {
    for (const char* c : {"A", "P1", "P2", "S010", "S025", "S040", "S060", "S080"}) {
      expected.push_back(h + std::string(c) + "_R1");
    }
  }
  // The transfer channels T<k>_SH<i>, k = 0..K (docs/sweep.md, "Transfer").
  for (int k = 0; k <= 2; ++k) {
    for (int i = 0; i < 9; ++i)
      expected.push_back("T" + std::to_string(k) + "_SH" + std::to_string(i));
  }
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(names, expected);
  EXPECT_EQ(image.attributes.at("gtbake.spp"), "16");
  EXPECT_EQ(image.attributes.at("gtbake.bounces"), "2");
  EXPECT_EQ(image.attributes.at("gtbake.radius"), "inf");
  EXPECT_EQ(image.attributes.at("gtbake.specular_roughness"), "0.1,0.25,0.4,0.6,0.8");
  EXPECT_EQ(image.attributes.at("gtbake.specular_spp"), "64");
  EXPECT_EQ(image.attributes.at("gtbake.gbuffer_radii"), "1");
  EXPECT_EQ(image.attributes.at("gtbake.transfer"), "1");

  const auto& a = image.channel("A", "");
  const auto& p1 = image.channel("P1", "");
  const auto& p2 = image.channel("P2", "");
  const auto& g050 = image.channel("G050", "");
  const auto& mask = image.channel("mask", "");
  std::size_t geometry = 0;
  for (std::size_t p = 0; p < a.size(); ++p) {
    if (mask[p] == 0.0f) {
      EXPECT_EQ(a[p], 0.0f);
      EXPECT_EQ(g050[p], 0.0f);
      continue;
    }
    ++geometry;
    // The full estimate is the mean of the two half-sample estimates.
    for (const std::string k : {"A", "P1", "P2"}) {
      const float full = image.channel(k, "")[p];
      const float mean = 0.5f * (image.channel("H0." + k, "")[p] + image.channel("H1." + k, "")[p]);
      EXPECT_NEAR(full, mean, 1e-6f) << k;
    }
    EXPECT_NEAR(g050[p], a[p] + 0.5f * p1[p] + 0.25f * p2[p], 1e-6f);
  }
  EXPECT_GT(geometry, 0u);

  std::ifstream in(o.out / "sweep.json");
  const nlohmann::json json = nlohmann::json::parse(in);
  EXPECT_EQ(json["settings"]["spp"], 16);
  EXPECT_EQ(json["settings"]["bounces"], 2);
  EXPECT_TRUE(json["settings"]["radius"].is_null());
  EXPECT_EQ(json["settings"]["albedos"].size(), 7u);
  EXPECT_EQ(json["settings"]["specular_roughness"].size(), 5u);
  EXPECT_EQ(json["settings"]["specular_spp"], 64);
  ASSERT_EQ(json["views"].size(), 1u);
  EXPECT_EQ(json["views"][0]["name"], "spheres");
  EXPECT_EQ(json["views"][0]["file"], "spheres.exr");
  // The camera the sweep traced with, serialised whole (docs/sweep.md, "G-buffer").
  const PerspectiveCamera traced = makeSphereOnPlaneScene(1.0).camera;
  const PerspectiveCamera read = cameraFromJson(json["views"][0]["camera"], "sweep.json");
  EXPECT_EQ(read.position, traced.position);
  EXPECT_EQ(read.basis, traced.basis);
  EXPECT_EQ(read.yfov, traced.yfov);
  EXPECT_EQ(json["settings"]["gbuffer_radii"], nlohmann::json::array({1.0}));
  EXPECT_EQ(json["views"][0]["unmasked_pixels"], geometry);
  EXPECT_EQ(json["views"][0]["rays"], result.rays);
  EXPECT_TRUE(json["totals"]["rays_per_second"].is_number());
  EXPECT_TRUE(fs::exists(o.out / "spheres_G050.png"));
  for (const auto& entry : fs::directory_iterator(o.out)) {
    EXPECT_EQ(entry.path().string().find(".gtbake-"), std::string::npos) << entry.path();
  }
}

// docs/sweep.md, "Transfer": under the uniform white sky (L = 1, whose only SH coefficient is
// L_0 = 2√π) Σ_k ρ^k ⟨T_k, L⟩ is today's G to rounding, bounce by bounce T_{k,0}·2√π = p̂_k; the
// l = 1 part of T_0 points along the bent normal; --transfer off drops the channels and nothing
// else changes.
TEST_F(SweepCommand, TransferUnderUniformSkyReproducesG) {
  const fs::path scene = writeScene(makeSphereOnPlaneScene(1.0), "spheres");
  SweepOptions o = options(scene, "on");
  runSweep(o);
  const ExrImage image = readExr(o.out / "spheres.exr");
  const double sky = 2.0 * std::sqrt(3.14159265358979323846);
  const auto& mask = image.channel("mask", "");
  for (std::size_t p = 0; p < mask.size(); ++p) {
    double g = 0.0;
    for (int k = 3; k >= 0; --k) {
      const double t0 = image.channel("T" + std::to_string(k) + "_SH0", "")[p];
      const std::string pk = k == 0 ? "A" : "P" + std::to_string(k);
      EXPECT_NEAR(t0 * sky, image.channel(pk, "")[p], 1e-6) << p << " " << k;
      g = g * 0.5 + t0 * sky;
    }
    EXPECT_NEAR(g, image.channel("G050", "")[p], 1e-6) << p;
    if (mask[p] == 0.0f || image.channel("A", "")[p] == 0.0f) continue;
    // Y1 ∝ y, Y2 ∝ z, Y3 ∝ x: T_0's band 1 is the unnormalised bent normal.
    const Eigen::Vector3d b(image.channel("T0_SH3", "")[p], image.channel("T0_SH1", "")[p],
                            image.channel("T0_SH2", "")[p]);
    const Eigen::Vector3d bent(image.channel("BNX", "")[p], image.channel("BNY", "")[p],
                               image.channel("BNZ", "")[p]);
    EXPECT_NEAR(b.normalized().dot(bent), 1.0, 1e-4) << p;
  }
  SweepOptions off = options(scene, "off");
  off.transfer = false;
  runSweep(off);
  const ExrImage without = readExr(off.out / "spheres.exr");
  EXPECT_EQ(without.channels.size() + 36, image.channels.size());
  EXPECT_EQ(without.attributes.at("gtbake.transfer"), "0");
  for (const auto& [name, pixels] : without.channels) EXPECT_EQ(pixels, image.channel(name, ""));
}

// The bowl of the scene library seen through the camera: pixels whose rays enter the opening
// within half its radius see the deep part of the bowl, where A = 1 − h/(2R) holds to < 1% on
// the mesh (see ClosedForm.SphericalCavity for the tessellation measurement).
TEST_F(SweepCommand, SphericalCavityThroughThePixels) {
  const double radius = 1.0;
  const double depth = 1.4;
  const Scene bowl = makeSphericalCavityScene(radius, depth);
  const fs::path scene = writeScene(bowl, "cavity");
  SweepOptions o = options(scene, "out");
  o.width = 64;
  o.height = 64;
  o.spp = 256;
  o.bounces = 1;  // A does not depend on K (a sweep needs K >= 1: fit reads P1)
  runSweep(o);
  const ExrImage image = readExr(o.out / "cavity.exr");
  const auto& a = image.channel("A", "");
  const double rim = std::sqrt(depth * (2.0 * radius - depth));
  double sum = 0.0;
  double n = 0.0;
  for (int j = 0; j < o.height; ++j) {
    for (int i = 0; i < o.width; ++i) {
      const Ray ray = cameraRay(bowl.camera, i, j, o.width, o.height);
      const double t = -ray.origin.y() / ray.direction.y();  // where it crosses the ground plane
      const double r = std::hypot(ray.origin.x() + t * ray.direction.x(),
                                  ray.origin.z() + t * ray.direction.z());
      if (r < 0.5 * rim) {
        sum += a[static_cast<std::size_t>(j) * o.width + i];
        n += 1.0;
      }
    }
  }
  ASSERT_GT(n, 100.0);
  const double a_smooth = 1.0 - depth / (2.0 * radius);
  const double se = std::sqrt(a_smooth * (1.0 - a_smooth) / (n * o.spp));
  EXPECT_NEAR(sum / n, a_smooth, 3.0 * se + 0.01 * a_smooth);
}

TEST_F(SweepCommand, RejectsBadOptionsWithoutOutput) {
  const fs::path scene = writeScene(makeOpenPlaneScene(), "plane");
  SweepOptions o = options(scene, "out");
  o.spp = 15;
  expectRejected(o, "--spp");
  o.spp = 0;
  expectRejected(o, "--spp");
  o.spp = (1 << 20) + 2;
  expectRejected(o, "--spp");
  o = options(scene, "out");
  o.width = 0;
  expectRejected(o, "--res");
  o.width = 8193;
  expectRejected(o, "--res");
  o = options(scene, "out");
  o.bounces = 17;
  expectRejected(o, "--bounces");
  o = options(scene, "out");
  o.radius = 0.0;
  expectRejected(o, "--radius");
  o.radius = -1.0;
  expectRejected(o, "--radius");
  o = options(scene, "out");
  o.specular_roughness = {0.1, 1.2};
  expectRejected(o, "--specular-roughness");
  o.specular_roughness = {0.1, 0.101};  // both S010
  expectRejected(o, "--specular-roughness");
  o.specular_roughness = {0.5};
  o.specular_spp = 7;
  expectRejected(o, "--specular-spp");
  o = options(scene, "out");
  o.scenes.clear();
  expectRejected(o, "no scenes");
  o = options(root_ / "scenes" / "missing.gltf", "out");
  expectRejected(o, "missing.gltf");
  o = options(root_ / "empty_dir", "out");
  fs::create_directories(root_ / "empty_dir");
  expectRejected(o, "no .gltf files");
}

// A glTF without a camera gets kAutoViews automatic views, one image each, named <stem>_v<k>
// and clustered by the file; a scene with a camera keeps its one image. View k is traced with
// exactly autoCameras(scene)[k]: the same scene written with that camera and swept under the
// view's name gives the same pixels.
TEST_F(SweepCommand, SceneWithoutCameraGetsAutomaticViews) {
  const fs::path path = root_ / "scenes" / "nocamera.gltf";
  std::ofstream(path) << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
    "nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
                  "min":[0,0,0],"max":[1,1,0]}],
    "bufferViews":[{"buffer":0,"byteLength":36}],
    "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})";
  const fs::path good = writeScene(makeOpenPlaneScene(), "plane");
  SweepOptions o = options(good, "out");
  o.scenes = {good, path};
  runSweep(o);
  const nlohmann::json views = nlohmann::json::parse(readFile(o.out / "sweep.json"))["views"];
  ASSERT_EQ(views.size(), 1u + kAutoViews);
  EXPECT_EQ(views[0]["name"], "plane");
  EXPECT_EQ(views[0]["scene"], "plane");
  EXPECT_EQ(views[0]["type"], "open_plane");  // the generated file carries its type
  for (int k = 0; k < kAutoViews; ++k) {
    EXPECT_EQ(views[1 + k]["name"], "nocamera_v" + std::to_string(k));
    EXPECT_EQ(views[1 + k]["scene"], "nocamera");
    EXPECT_EQ(views[1 + k]["type"], "nocamera");  // no type in the file: the scene
    EXPECT_GT(views[1 + k]["unmasked_pixels"].get<int>(), 0);
    EXPECT_TRUE(fs::exists(o.out / ("nocamera_v" + std::to_string(k) + ".exr")));
  }
  // --camera auto:2 for the plane; view 1 against the plane written with that camera.
  SweepOptions two = options(good, "two");
  two.camera = "auto:2";
  runSweep(two);
  Scene plane = makeOpenPlaneScene();
  plane.camera = autoCameras(plane, 2, 40.0 / 30.0)[1];
  SweepOptions same = options(writeScene(plane, "plane_v1"), "same");
  runSweep(same);
  EXPECT_EQ(readFile(two.out / "plane_v1_A.png"), readFile(same.out / "plane_v1_A.png"));
  EXPECT_EQ(readFile(two.out / "plane_v1_G050.png"), readFile(same.out / "plane_v1_G050.png"));
  SweepOptions bad = options(good, "bad");
  bad.camera = "auto:0";
  expectRejected(bad, "auto:K");
}

TEST_F(SweepCommand, RejectsUnwritableOutput) {
  const fs::path scene = writeScene(makeOpenPlaneScene(), "plane");
  std::ofstream(root_ / "file") << "x";
  SweepOptions o = options(scene, "file");
  try {
    runSweep(o);
    ADD_FAILURE() << "wrote into a file path";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  EXPECT_EQ(readFile(root_ / "file"), "x");
}

}  // namespace
}  // namespace gtbake
