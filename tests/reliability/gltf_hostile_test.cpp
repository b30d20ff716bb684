// Hostile glTF inputs (docs/limits.md): cases that could crash, hang, read out of bounds or
// silently produce wrong geometry; each must be a one-line gtbake::Error (or the right result).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "reliability_util.h"
#include "scene/gltf_reader.h"
#include "scene/scene.h"
#include "sweep/sweep_command.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::ScopedEnv;
using test::spit;
using test::TempDir;

// A one-triangle glTF (positions at view 0 / accessor 0, u16 indices at view 1 / accessor 1)
// and a camera at node 1; tests edit `doc` before writing.
struct Gltf {
  json doc;
  std::string bin;

  Gltf() {
    const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::uint16_t idx[4] = {0, 1, 2, 0};
    bin.assign(reinterpret_cast<const char*>(p), sizeof(p));
    bin.append(reinterpret_cast<const char*>(idx), sizeof(idx));
    doc = {
        {"asset", {{"version", "2.0"}}},
        {"bufferViews",
         {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
          {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}}},
        {"accessors",
         {{{"bufferView", 0}, {"componentType", 5126}, {"type", "VEC3"}, {"count", 3}},
          {{"bufferView", 1}, {"componentType", 5123}, {"type", "SCALAR"}, {"count", 3}}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
        {"cameras", {{{"type", "perspective"}, {"perspective", {{"yfov", 0.6}, {"znear", 0.1}}}}}},
        {"nodes", {{{"mesh", 0}}, {{"camera", 0}, {"translation", {0, 0, 5}}}}},
        {"scenes", {{{"nodes", {0, 1}}}}},
        {"scene", 0}};
  }
  fs::path write(const fs::path& dir, const std::string& name = "s") {
    if (!doc.contains("buffers")) {
      doc["buffers"] = json::array({{{"uri", name + ".bin"}, {"byteLength", bin.size()}}});
    }
    spit(dir / (name + ".bin"), bin);
    spit(dir / (name + ".gltf"), doc.dump());
    return dir / (name + ".gltf");
  }
};

std::string errorOf(const fs::path& path, const GltfReadOptions& options = {}) {
  try {
    readGltfScene(path, options);
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    return message;
  }
  return "";
}

void expectError(const fs::path& path, const std::string& fragment,
                 const GltfReadOptions& options = {}) {
  const std::string message = errorOf(path, options);
  EXPECT_NE(message.find(fragment), std::string::npos) << "got: '" << message << "'";
}

TEST(GltfHostile, BaselineReads) {
  TempDir dir("gltf_ok");
  Gltf g;
  const Scene scene = readGltfScene(g.write(dir.path()), {});
  EXPECT_EQ(scene.triangles.size(), 1u);
}

// count and byteOffset that wrap size_t arithmetic used to pass the bounds check.
TEST(GltfHostile, WrappingAccessorCountOrOffsetIsRefused) {
  TempDir dir("gltf_wrap");
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, std::uint64_t>>{{"count", 0x4000000000000001ull},
                                                          {"count", 0x1555555555555556ull},
                                                          {"byteOffset", 0xFFFFFFFFFFFFFFF0ull}}) {
    Gltf g;
    g.doc["accessors"][0][key] = value;
    const std::string message = errorOf(g.write(dir.path()));
    EXPECT_FALSE(message.empty()) << key << "=" << value;
  }
  Gltf g;
  g.doc["bufferViews"][0]["byteOffset"] = 0xFFFFFFFFFFFFFFF0ull;
  EXPECT_FALSE(errorOf(g.write(dir.path())).empty());
  Gltf h;
  h.doc["accessors"][1]["count"] = 0x8000000000000001ull;  // index accessor
  EXPECT_FALSE(errorOf(h.write(dir.path())).empty());
}

TEST(GltfHostile, DeepNodeChainIsWalkedWithoutRecursion) {
  TempDir dir("gltf_deep");
  Gltf g;
  const int depth = 20000;
  json nodes = json::array();
  for (int i = 0; i < depth; ++i) nodes.push_back({{"children", {i + 1}}});
  nodes.push_back({{"mesh", 0}});
  nodes.push_back({{"camera", 0}, {"translation", {0, 0, 5}}});
  g.doc["nodes"] = nodes;
  g.doc["scenes"] = json::array({{{"nodes", {0, depth + 1}}}});
  const Scene scene = readGltfScene(g.write(dir.path()), {});
  EXPECT_EQ(scene.triangles.size(), 1u);
}

TEST(GltfHostile, DeeplyNestedJsonIsRefusedBeforeParsing) {
  TempDir dir("gltf_nest");
  Gltf g;
  const fs::path path = g.write(dir.path());
  std::string text = test::readBytes(path);
  text.insert(1, "\"extras\":" + std::string(100000, '[') + std::string(100000, ']') + ",");
  spit(path, text);
  expectError(path, "GTBAKE_MAX_JSON_DEPTH");
}

TEST(GltfHostile, DuplicatedChildrenCannotExplodeInstances) {
  TempDir dir("gltf_dup");
  Gltf g;
  json nodes = json::array();
  for (int i = 0; i < 40; ++i) nodes.push_back({{"children", {i + 1, i + 1}}});
  nodes.push_back({{"mesh", 0}});
  nodes.push_back({{"camera", 0}, {"translation", {0, 0, 5}}});
  g.doc["nodes"] = nodes;
  g.doc["scenes"] = json::array({{{"nodes", {0, 41}}}});
  expectError(g.write(dir.path()), "GTBAKE_MAX_INSTANCES");
}

TEST(GltfHostile, TriangleAndVertexLimitsNameTheirVariable) {
  TempDir dir("gltf_limits");
  Gltf g;
  g.doc["nodes"][0]["children"] = {2};
  g.doc["nodes"].push_back({{"mesh", 0}});
  const fs::path path = g.write(dir.path());
  {
    const ScopedEnv limit("GTBAKE_MAX_TRIANGLES", "1");
    expectError(path, "GTBAKE_MAX_TRIANGLES");
  }
  {
    const ScopedEnv limit("GTBAKE_MAX_VERTICES", "5");
    expectError(path, "GTBAKE_MAX_VERTICES");
  }
  EXPECT_EQ(readGltfScene(path, {}).triangles.size(), 2u);
}

TEST(GltfHostile, FifoBufferIsRefusedNotWaitedOn) {
  TempDir dir("gltf_fifo");
  Gltf g;
  g.doc["buffers"] = json::array({{{"uri", "pipe.bin"}, {"byteLength", g.bin.size()}}});
  const fs::path path = g.write(dir.path());
  ASSERT_EQ(::mkfifo((dir.path() / "pipe.bin").c_str(), 0600), 0);
  expectError(path, "not a regular file");
  // The glTF itself named as a FIFO.
  ASSERT_EQ(::mkfifo((dir.path() / "f.gltf").c_str(), 0600), 0);
  expectError(dir.path() / "f.gltf", "not a regular file");
}

TEST(GltfHostile, UrisOutsideTheDirectoryAreRefused) {
  TempDir dir("gltf_paths");
  fs::create_directories(dir.path() / "scenes");
  Gltf g;
  spit(dir.path() / "outside.bin", g.bin);
  for (const std::string& uri :
       std::vector<std::string>{"../outside.bin", "%2e%2e/outside.bin", "%2E%2E%2Foutside.bin",
                                "sub/../../outside.bin", (dir.path() / "outside.bin").string()}) {
    Gltf h;
    h.doc["buffers"] = json::array({{{"uri", uri}, {"byteLength", h.bin.size()}}});
    const fs::path path = h.write(dir.path() / "scenes");
    const std::string message = errorOf(path);
    EXPECT_TRUE(message.find("outside") != std::string::npos ||
                message.find("absolute") != std::string::npos)
        << uri << ": " << message;
  }
  // Explicitly allowed.
  Gltf h;
  h.doc["buffers"] = json::array({{{"uri", "../outside.bin"}, {"byteLength", h.bin.size()}}});
  const fs::path path = h.write(dir.path() / "scenes");
  GltfReadOptions allow;
  allow.allow_outside = true;
  EXPECT_EQ(readGltfScene(path, allow).triangles.size(), 1u);
}

// tinygltf falls back to "./uri" for a buffer missing beside the glTF; the reader must not.
TEST(GltfHostile, MissingBufferIsNotSearchedInTheCurrentDirectory) {
  TempDir dir("gltf_cwd");
  fs::create_directories(dir.path() / "scenes");
  fs::create_directories(dir.path() / "cwd");
  Gltf g;
  g.doc["buffers"] = json::array({{{"uri", "only_in_cwd.bin"}, {"byteLength", g.bin.size()}}});
  const fs::path path = g.write(dir.path() / "scenes");
  spit(dir.path() / "cwd" / "only_in_cwd.bin", g.bin);
  const fs::path old = fs::current_path();
  fs::current_path(dir.path() / "cwd");
  const std::string message = errorOf(fs::absolute(path));
  fs::current_path(old);
  EXPECT_NE(message.find("only_in_cwd.bin"), std::string::npos) << message;
}

TEST(GltfHostile, AbsurdCameraAndVerticesAreRefused) {
  TempDir dir("gltf_far");
  {
    Gltf g;
    g.doc["nodes"][1]["translation"] = {0, 0, 1e18};
    expectError(g.write(dir.path()), "GTBAKE_MAX_COORDINATE");
  }
  {
    Gltf g;
    g.doc["nodes"][0]["scale"] = {1e12, 1e12, 1e12};
    expectError(g.write(dir.path()), "GTBAKE_MAX_COORDINATE");
  }
  {
    Gltf g;
    g.doc["nodes"][1]["scale"] = {0, 0, 0};
    expectError(g.write(dir.path()), "zero scale");
  }
  {
    Gltf g;
    g.doc["nodes"][1]["scale"] = {-1, 1, 1};
    expectError(g.write(dir.path()), "mirroring");
  }
}

TEST(GltfHostile, CameraChosenByNameOrIndex) {
  TempDir dir("gltf_cams");
  Gltf g;
  g.doc["cameras"][0]["name"] = "wide";
  g.doc["cameras"].push_back({{"name", "tele"},
                              {"type", "perspective"},
                              {"perspective", {{"yfov", 0.2}, {"znear", 0.1}}}});
  g.doc["nodes"].push_back({{"camera", 1}, {"translation", {0, 0, 9}}});
  g.doc["scenes"][0]["nodes"] = {0, 1, 2};
  const fs::path path = g.write(dir.path());
  GltfReadInfo info;
  EXPECT_DOUBLE_EQ(readGltfScene(path, {}, &info).camera.yfov, 0.6);
  EXPECT_EQ(info.perspective_cameras, 2);
  EXPECT_EQ(info.camera_name, "wide");
  GltfReadOptions by_name;
  by_name.camera = "tele";
  EXPECT_DOUBLE_EQ(readGltfScene(path, by_name).camera.yfov, 0.2);
  GltfReadOptions by_index;
  by_index.camera = "1";
  EXPECT_DOUBLE_EQ(readGltfScene(path, by_index).camera.position.z(), 9.0);
  by_index.camera = "2";
  expectError(path, "numbered from 0", by_index);
  by_name.camera = "nope";
  expectError(path, "no perspective camera", by_name);
}

// '+' in a uri is a plus sign (docs/limits.md §Paths): with "a b.bin" beside "a+b.bin", each
// uri reads its own file, also in a .glb, and a missing "a+b.bin" is named as such.
TEST(GltfHostile, PlusInAUriIsAPlusNotASpace) {
  TempDir dir("gltf_plus");
  Gltf g;
  std::string other = g.bin;  // the same triangle, x of its second vertex 1 -> 7
  const float seven = 7.0f;
  std::memcpy(other.data() + 12, &seven, 4);
  spit(dir.path() / "a b.bin", g.bin);
  spit(dir.path() / "a+b.bin", other);
  g.doc["buffers"] = json::array({{{"uri", "a%20b.bin"}, {"byteLength", g.bin.size()}},
                                  {{"uri", "a+b.bin"}, {"byteLength", other.size()}}});
  g.doc["bufferViews"][0]["buffer"] = 1;
  const fs::path path = g.write(dir.path());
  EXPECT_FLOAT_EQ(readGltfScene(path).positions[1].x(), 7.0f);
  std::string text = g.doc.dump();  // as a .glb without a BIN chunk: the buffers stay external
  text.append((4 - text.size() % 4) % 4, ' ');
  const auto u32 = [](std::size_t v) {
    const auto value = static_cast<std::uint32_t>(v);
    return std::string(reinterpret_cast<const char*>(&value), 4);
  };
  spit(dir.path() / "s.glb",
       "glTF" + u32(2) + u32(20 + text.size()) + u32(text.size()) + "JSON" + text);
  EXPECT_FLOAT_EQ(readGltfScene(dir.path() / "s.glb").positions[1].x(), 7.0f);
  fs::remove(dir.path() / "a+b.bin");
  const std::string message = errorOf(path);
  EXPECT_NE(message.find("a+b.bin"), std::string::npos) << message;
  EXPECT_EQ(message.find("a b.bin"), std::string::npos) << message;
}

// glTF 1.0 (asset.version 1.0, or no asset and dictionaries where 2.0 has arrays, or a .glb of
// version 1) is named as such, with how to convert it.
TEST(GltfHostile, Gltf1IsNamedWithItsConversion) {
  TempDir dir("gltf_v1");
  Gltf g;
  g.doc["asset"]["version"] = "1.0";
  expectError(g.write(dir.path()), "glTF 1.0 is not supported");
  expectError(g.write(dir.path()), "assimp export in.gltf out.gltf -f gltf2");
  Gltf keyed;
  keyed.doc.erase("asset");
  keyed.doc["meshes"] = {{"mesh_0", keyed.doc["meshes"][0]}};
  expectError(keyed.write(dir.path()), "glTF 1.0 is not supported");
  spit(dir.path() / "v1.glb", std::string("glTF\x01\0\0\0\x14\0\0\0\0\0\0\0\0\0\0\0", 20));
  expectError(dir.path() / "v1.glb", "binary glTF 1.0 (.glb version 1) is not supported");
}

// A scene whose only camera is orthographic is swept from automatic views, and stderr says in
// one line which camera was ignored and why.
TEST(GltfHostile, IgnoredOrthographicCameraIsNamed) {
  TempDir dir("gltf_ortho");
  Gltf g;
  g.doc["cameras"][0] = {{"name", "top\nview"},
                         {"type", "orthographic"},
                         {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 9}}}};
  SweepOptions o;
  o.scenes = {g.write(dir.path())};
  o.out = dir.path() / "sweep";
  o.spp = 2;
  o.width = o.height = 8;
  o.threads = 1;
  o.progress = false;
  testing::internal::CaptureStderr();
  runSweep(o);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("ignoring orthographic camera 'top?view' (gtbake traces perspective views "
                     "only); using 4 automatic views"),
            std::string::npos)
      << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_TRUE(fs::exists(o.out / "s_v0.exr"));
}

TEST(GltfHostile, TruncatedAndForgedGlbAreErrors) {
  TempDir dir("gltf_glb");
  std::string glb = "glTF";
  const std::uint32_t header[4] = {2, 0xFFFFFFF0u, 0xFFFFFFF0u, 0x4E4F534Au};
  glb.append(reinterpret_cast<const char*>(header), sizeof(header));
  glb += "{}";
  spit(dir.path() / "x.glb", glb);
  EXPECT_FALSE(errorOf(dir.path() / "x.glb").empty());
  spit(dir.path() / "y.glb", "glT");
  EXPECT_FALSE(errorOf(dir.path() / "y.glb").empty());
}

}  // namespace
}  // namespace gtbake
