// readGltfScene / writeGltfScene: round trips, determinism, transforms and one-line errors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "scene/procedural_scenes.h"
#include "scene/scene.h"
#include "scene/scenes_command.h"
#include "scene_test_util.h"
#include "support/test_scenes.h"

namespace gtbake {
namespace {

using nlohmann::json;
using test::TempDir;

// Every generated scene type, plus the closed-form ones, reads back bit-identical.
TEST(GltfRoundTrip, EveryProceduralSceneReadsBackIdentical) {
  TempDir dir("roundtrip");
  std::vector<Scene> scenes;
  for (const auto& name : sceneTypeNames()) scenes.push_back(makeSceneType(name, 7));
  scenes.push_back(makeSphericalCavityScene(1.0, 0.7, 32));
  scenes.push_back(makeVGrooveScene(1.0, 1.0));
  scenes.push_back(makeClosedBoxScene());
  for (const Scene& scene : scenes) {
    const auto path = dir.path() / (scene.name + ".gltf");
    writeGltfScene(path, scene);
    const Scene back = readGltfScene(path);
    EXPECT_TRUE(test::scenesIdentical(scene, back)) << scene.name;
    EXPECT_EQ(back.positions.size(), scene.positions.size()) << scene.name;
  }
  // No temporary files or directories are left behind.
  std::size_t entries = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path().string().find(".gtbake-"), std::string::npos) << entry.path();
    ++entries;
  }
  EXPECT_EQ(entries, 2 * scenes.size());
}

// runScenes twice gives the same bytes, in the fixed order, seeded by the seed alone.
TEST(ScenesCommand, SameSeedSameBytesOtherSeedOtherTerrain) {
  TempDir a("bytes_a"), b("bytes_b"), c("bytes_c");
  const auto classic = [](const std::filesystem::path& out, std::uint64_t seed) {
    ScenesOptions options;
    options.out = out;
    options.seed = seed;
    options.classic = true;
    options.progress = false;
    return runScenes(options);
  };
  const auto paths_a = classic(a.path(), 1);
  const auto paths_b = classic(b.path(), 1);
  const auto paths_c = classic(c.path(), 2);
  ASSERT_EQ(paths_a.size(), 7u);
  for (std::size_t k = 0; k < 7; ++k) {
    EXPECT_EQ(paths_a[k].stem().string(), sceneTypeNames()[k]);
    for (const char* ext : {".gltf", ".bin"}) {
      const auto pa = std::filesystem::path(paths_a[k]).replace_extension(ext);
      const auto pb = std::filesystem::path(paths_b[k]).replace_extension(ext);
      const auto pc = std::filesystem::path(paths_c[k]).replace_extension(ext);
      const std::string bytes = test::readBytes(pa);
      EXPECT_FALSE(bytes.empty());
      EXPECT_EQ(bytes, test::readBytes(pb)) << pa;
      const bool seeded = k >= 5;  // clutter, terrain
      if (seeded && std::string(ext) == ".bin") {
        EXPECT_NE(bytes, test::readBytes(pc)) << pa;
      }
      if (!seeded) {
        EXPECT_EQ(bytes, test::readBytes(pc)) << pa;
      }
    }
  }
}

// A hand-written file: float data and u16/u8 indices in one buffer.
struct HandWritten {
  json doc;
  std::string bin;

  int addBytes(const void* data, std::size_t size, int stride = 0) {
    while (bin.size() % 4) bin.push_back('\0');
    json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", size}};
    if (stride) view["byteStride"] = stride;
    bin.append(static_cast<const char*>(data), size);
    doc["bufferViews"].push_back(view);
    return static_cast<int>(doc["bufferViews"].size()) - 1;
  }
  int addAccessor(int view, int component, const char* type, std::size_t count, int offset = 0) {
    doc["accessors"].push_back({{"bufferView", view},
                                {"componentType", component},
                                {"type", type},
                                {"count", count},
                                {"byteOffset", offset}});
    return static_cast<int>(doc["accessors"].size()) - 1;
  }
  std::filesystem::path write(const std::filesystem::path& dir, const std::string& name) {
    doc["asset"] = {{"version", "2.0"}};
    doc["buffers"] = json::array({{{"uri", name + ".bin"}, {"byteLength", bin.size()}}});
    std::ofstream(dir / (name + ".bin"), std::ios::binary) << bin;
    std::ofstream(dir / (name + ".gltf")) << doc.dump(1);
    return dir / (name + ".gltf");
  }
};

// One triangle (0,0,0), (1,0,0), (0,1,0) with u16 indices; a perspective camera node.
HandWritten oneTriangle() {
  HandWritten h;
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint16_t idx[3] = {0, 1, 2};
  const int pos = h.addAccessor(h.addBytes(p, sizeof(p)), 5126, "VEC3", 3);
  const int ind = h.addAccessor(h.addBytes(idx, sizeof(idx)), 5123, "SCALAR", 3);
  h.doc["meshes"] =
      json::array({{{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", ind}}}}}});
  h.doc["cameras"] =
      json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.6}, {"znear", 0.1}}}}});
  h.doc["nodes"] = json::array({{{"mesh", 0}}, {{"camera", 0}, {"translation", {0, 0, 5}}}});
  h.doc["scenes"] = json::array({{{"nodes", {0, 1}}}});
  h.doc["scene"] = 0;
  return h;
}

TEST(GltfRead, NodeHierarchyTransformsGeometryAndCamera) {
  TempDir dir("transforms");
  HandWritten h = oneTriangle();
  const double s = std::sqrt(0.5);
  // Parent: translate (1, 2, 3) ∘ rotate 90° about +Z; child: scale 2 holding the mesh.
  // Camera: under a parent scaled ×3, translated (0, 0, 5) and turned 90° about +Y.
  h.doc["nodes"] =
      json::array({{{"translation", {1, 2, 3}}, {"rotation", {0, 0, s, s}}, {"children", {1}}},
                   {{"scale", {2, 2, 2}}, {"mesh", 0}},
                   {{"scale", {3, 3, 3}}, {"children", {3}}},
                   {{"camera", 0}, {"translation", {0, 0, 5}}, {"rotation", {0, s, 0, s}}}});
  h.doc["scenes"] = json::array({{{"nodes", {0, 2}}, {"name", "hand"}}});
  const Scene scene = readGltfScene(h.write(dir.path(), "hand"));
  EXPECT_EQ(scene.name, "hand");
  ASSERT_EQ(scene.positions.size(), 3u);
  // p ↦ (1,2,3) + Rz(90°)(2p): (1,0,0) → (1,4,3); (0,1,0) → (−1,2,3).
  EXPECT_TRUE(scene.positions[0].isApprox(Eigen::Vector3f(1, 2, 3), 1e-6f));
  EXPECT_TRUE(scene.positions[1].isApprox(Eigen::Vector3f(1, 4, 3), 1e-6f));
  EXPECT_TRUE(scene.positions[2].isApprox(Eigen::Vector3f(-1, 2, 3), 1e-6f));
  EXPECT_TRUE(scene.camera.position.isApprox(Eigen::Vector3d(0, 0, 15), 1e-12));
  Eigen::Matrix3d expected;
  expected << 0, 0, 1, 0, 1, 0, -1, 0, 0;  // columns: Ry(90°) x, y, z axes
  EXPECT_TRUE(scene.camera.basis.isApprox(expected, 1e-12)) << scene.camera.basis;
  EXPECT_DOUBLE_EQ(scene.camera.yfov, 0.6);
}

TEST(GltfRead, InterleavedNonIndexedAndU8AndMirrored) {
  TempDir dir("layouts");
  HandWritten h = oneTriangle();
  // Interleaved vertices (position after a 4-byte pad, stride 16), a second, non-indexed
  // primitive reading the same view with an accessor offset, and u8 indices.
  const float v[12] = {9, 1, 0, 0, 9, 0, 1, 0, 9, 0, 0, 1};
  const int view = h.addBytes(v, sizeof(v), 16);
  const int interleaved = h.addAccessor(view, 5126, "VEC3", 3, 4);
  const std::uint8_t idx[3] = {2, 1, 0};
  const int u8 = h.addAccessor(h.addBytes(idx, 3), 5121, "SCALAR", 3);
  h.doc["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", interleaved}}}});
  h.doc["meshes"][0]["primitives"].push_back(
      {{"attributes", {{"POSITION", interleaved}}}, {"indices", u8}});
  h.doc["nodes"][0]["scale"] = {-1, 1, 1};  // mirrored: windings flip
  const Scene scene = readGltfScene(h.write(dir.path(), "layouts"));
  ASSERT_EQ(scene.positions.size(), 9u);
  ASSERT_EQ(scene.triangles.size(), 3u);
  EXPECT_EQ(scene.positions[3], Eigen::Vector3f(-1, 0, 0));
  EXPECT_EQ(scene.positions[4], Eigen::Vector3f(0, 1, 0));
  EXPECT_EQ(scene.positions[5], Eigen::Vector3f(0, 0, 1));
  EXPECT_EQ(scene.triangles[0], (std::array<std::uint32_t, 3>{0, 2, 1}));
  EXPECT_EQ(scene.triangles[1], (std::array<std::uint32_t, 3>{3, 5, 4}));
  EXPECT_EQ(scene.triangles[2], (std::array<std::uint32_t, 3>{8, 6, 7}));
}

TEST(GltfRead, GlbAndDefaultScene) {
  TempDir dir("glb");
  HandWritten h = oneTriangle();
  // Scene 1 (the default) holds the mesh under a node translated by (0, 0, −2).
  h.doc["nodes"].push_back({{"mesh", 0}, {"translation", {0, 0, -2}}});
  h.doc["scenes"].push_back({{"nodes", {2, 1}}, {"name", "second"}});
  h.doc["scene"] = 1;
  h.doc["asset"] = {{"version", "2.0"}};
  while (h.bin.size() % 4) h.bin.push_back('\0');
  h.doc["buffers"] = json::array({{{"byteLength", h.bin.size()}}});
  std::string text = h.doc.dump();
  while (text.size() % 4) text.push_back(' ');
  std::string glb;
  const auto word = [&glb](std::uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
  word(0x46546C67);  // "glTF"
  word(2);
  word(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + h.bin.size()));
  word(static_cast<std::uint32_t>(text.size()));
  word(0x4E4F534A);  // JSON
  glb += text;
  word(static_cast<std::uint32_t>(h.bin.size()));
  word(0x004E4942);  // BIN
  glb += h.bin;
  std::ofstream(dir.path() / "two.glb", std::ios::binary) << glb;
  const Scene scene = readGltfScene(dir.path() / "two.glb");
  EXPECT_EQ(scene.name, "second");
  ASSERT_EQ(scene.positions.size(), 3u);
  EXPECT_EQ(scene.positions[1], Eigen::Vector3f(1, 0, -2));
  EXPECT_EQ(scene.camera.position, Eigen::Vector3d(0, 0, 5));
}

// The error a bad file raises: a gtbake::Error whose message is one line naming the file.
std::string errorOf(const std::filesystem::path& path) {
  try {
    readGltfScene(path);
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find(path.filename().string()), std::string::npos) << message;
    return message;
  }
  ADD_FAILURE() << path << " was accepted";
  return "";
}

TEST(GltfRead, BadInputGivesOneLineErrors) {
  TempDir dir("bad");
  EXPECT_NE(errorOf(dir.path() / "missing.gltf").find("no such file"), std::string::npos);
  std::ofstream(dir.path() / "malformed.gltf") << "{ \"asset\": {\"version\": \"2.0\"}, oops";
  EXPECT_NE(errorOf(dir.path() / "malformed.gltf").find("not a valid glTF"), std::string::npos);

  HandWritten no_camera = oneTriangle();
  no_camera.doc["scenes"][0]["nodes"] = {0};
  EXPECT_NE(errorOf(no_camera.write(dir.path(), "no_camera")).find("no camera"), std::string::npos);

  HandWritten ortho = oneTriangle();
  ortho.doc["cameras"][0] = {
      {"type", "orthographic"},
      {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}};
  EXPECT_NE(errorOf(ortho.write(dir.path(), "ortho")).find("orthographic"), std::string::npos);

  HandWritten lines = oneTriangle();
  lines.doc["meshes"][0]["primitives"][0]["mode"] = 1;
  EXPECT_NE(errorOf(lines.write(dir.path(), "lines")).find("LINES"), std::string::npos);
  HandWritten loop = oneTriangle();
  loop.doc["meshes"][0]["primitives"][0]["mode"] = 2;
  EXPECT_NE(errorOf(loop.write(dir.path(), "loop")).find("LINE_LOOP"), std::string::npos);

  HandWritten no_triangles = oneTriangle();
  no_triangles.doc["scenes"][0]["nodes"] = {1};
  EXPECT_NE(errorOf(no_triangles.write(dir.path(), "empty")).find("no triangles"),
            std::string::npos);

  HandWritten out_of_range = oneTriangle();
  const std::uint16_t bad[3] = {0, 1, 7};
  out_of_range.doc["meshes"][0]["primitives"][0]["indices"] =
      out_of_range.addAccessor(out_of_range.addBytes(bad, sizeof(bad)), 5123, "SCALAR", 3);
  EXPECT_NE(errorOf(out_of_range.write(dir.path(), "range")).find("index 7"), std::string::npos);

  HandWritten nan = oneTriangle();
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, std::numeric_limits<float>::quiet_NaN(), 0};
  nan.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] =
      nan.addAccessor(nan.addBytes(p, sizeof(p)), 5126, "VEC3", 3);
  EXPECT_NE(errorOf(nan.write(dir.path(), "nan")).find("non-finite"), std::string::npos);

  // As Draco encoders write it: the accessors have no bufferView of their own, the primitive's
  // extension points at the compressed bytes. The error names the extension, not a bufferView.
  HandWritten draco = oneTriangle();
  draco.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  draco.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  for (auto& accessor : draco.doc["accessors"]) accessor.erase("bufferView");
  draco.doc["meshes"][0]["primitives"][0]["extensions"] = {
      {"KHR_draco_mesh_compression", {{"bufferView", 0}, {"attributes", {{"POSITION", 0}}}}}};
  const std::string message = errorOf(draco.write(dir.path(), "draco"));
  EXPECT_NE(message.find("unsupported extension KHR_draco_mesh_compression"), std::string::npos)
      << message;
  EXPECT_EQ(message.find("bufferView"), std::string::npos) << message;
}

// Strips and fans become triangles as glTF 2.0 §3.7.2.1 orders them (every strip triangle keeps
// the first one's winding; the degenerate joint of a stitched strip is dropped), with and without
// indices, and mirrored nodes still flip them.
TEST(GltfRead, TriangleStripsAndFansAreTriangulated) {
  TempDir dir("strips");
  HandWritten h = oneTriangle();
  const float square[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const int pos = h.addAccessor(h.addBytes(square, sizeof(square)), 5126, "VEC3", 4);
  const std::uint16_t strip[5] = {0, 1, 2, 3, 3};
  const std::uint16_t fan[4] = {0, 1, 3, 2};
  const int strip_idx = h.addAccessor(h.addBytes(strip, sizeof(strip)), 5123, "SCALAR", 5);
  const int fan_idx = h.addAccessor(h.addBytes(fan, sizeof(fan)), 5123, "SCALAR", 4);
  h.doc["meshes"][0]["primitives"] = {
      {{"attributes", {{"POSITION", pos}}}, {"indices", strip_idx}, {"mode", 5}},
      {{"attributes", {{"POSITION", pos}}}, {"indices", fan_idx}, {"mode", 6}},
      {{"attributes", {{"POSITION", pos}}}, {"mode", 5}}};
  const Scene scene = readGltfScene(h.write(dir.path(), "strips"));
  using Tri = std::array<std::uint32_t, 3>;
  const std::vector<Tri> expected = {{0, 1, 2},  {1, 3, 2},     // strip, joint (2, 3, 3) dropped
                                     {5, 7, 4},  {7, 6, 4},     // fan from vertex 4
                                     {8, 9, 10}, {9, 11, 10}};  // non-indexed strip
  EXPECT_EQ(scene.triangles, expected);
  for (const Tri& t : scene.triangles) {  // all face +Z, as the first strip triangle
    const Eigen::Vector3f n = (scene.positions[t[1]] - scene.positions[t[0]])
                                  .cross(scene.positions[t[2]] - scene.positions[t[0]]);
    EXPECT_GT(n.z(), 0.0f);
  }
  h.doc["nodes"][0]["scale"] = {-1, 1, 1};
  const Scene mirrored = readGltfScene(h.write(dir.path(), "mirrored"));
  ASSERT_EQ(mirrored.triangles.size(), expected.size());
  EXPECT_EQ(mirrored.triangles[1], (Tri{1, 2, 3}));
}

// The generated scenes carry their type; a file without one reads back with an empty type.
TEST(GltfRead, SceneTypeRoundTrips) {
  TempDir dir("types");
  Scene scene = makeCavityScene();
  scene.name = "bowls";
  scene.type = "cavity";
  writeGltfScene(dir.path() / "bowls.gltf", scene);
  EXPECT_EQ(readGltfScene(dir.path() / "bowls.gltf").type, "cavity");
  EXPECT_EQ(readGltfScene(oneTriangle().write(dir.path(), "plain")).type, "");
}

TEST(GltfWrite, RefusesOtherExtensionsAndKeepsOldFilesOnFailure) {
  TempDir dir("write");
  EXPECT_THROW(writeGltfScene(dir.path() / "x.glb", makeClosedBoxScene()), Error);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace gtbake
