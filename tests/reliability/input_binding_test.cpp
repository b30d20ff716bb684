// Inputs bound to their bytes and readers that never hang (docs/limits.md §Paths): the scene hash
// covers every file the loader reads (.gltf and .glb), percent-encoded uris name their files,
// images are never opened, and buffers that are not regular files or larger than their
// byteLength are refused before anything is read.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>

#include "common/input_limits.h"
#include "reliability_fixtures.h"
#include "scene/gltf_reader.h"
#include "sweep/merge_command.h"
#include "sweep/shard_manifest.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::readBytes;
using test::spit;
using test::TempDir;

// box.gltf + box.bin as writeGltfScene writes them, then the glTF's document for editing.
json writeBox(const fs::path& dir) {
  writeGltfScene(dir / "box.gltf", makeClosedBoxScene());
  return json::parse(readBytes(dir / "box.gltf"));
}

// The document as a .glb with no BIN chunk: its buffers stay external files.
void writeGlb(const fs::path& path, const json& doc) {
  std::string text = doc.dump();
  text.append((4 - text.size() % 4) % 4, ' ');
  const auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<char*>(&v), 4); };
  spit(path, "glTF" + u32(2) + u32(static_cast<std::uint32_t>(20 + text.size())) +
                 u32(static_cast<std::uint32_t>(text.size())) + "JSON" + text);
}

std::string inputHash(const fs::path& path) {
  GltfReadInfo info;
  readGltfScene(path, GltfReadOptions{}, &info);
  EXPECT_EQ(info.input_sha256.size(), 64u);
  return info.input_sha256;
}

// A file of `size` zero bytes that occupies no disk.
void sparseFile(const fs::path& path, std::uint64_t size) {
  spit(path, "");
  ASSERT_EQ(::truncate(path.c_str(), static_cast<off_t>(size)), 0);
}

// Flips one vertex coordinate of the buffer: the same size, other geometry.
void nudgeBuffer(const fs::path& bin) {
  std::string bytes = readBytes(bin);
  float x = 0.0f;
  std::memcpy(&x, bytes.data(), 4);
  x += 0.25f;
  std::memcpy(bytes.data(), &x, 4);
  spit(bin, bytes);
}

TEST(InputBinding, SceneHashCoversTheBuffersOfGltfAndGlb) {
  TempDir dir("binding_hash");
  json doc = writeBox(dir.path());
  writeGlb(dir.path() / "ext.glb", doc);
  const std::string gltf = inputHash(dir.path() / "box.gltf");
  const std::string glb = inputHash(dir.path() / "ext.glb");
  nudgeBuffer(dir.path() / "box.bin");
  EXPECT_NE(inputHash(dir.path() / "box.gltf"), gltf);
  EXPECT_NE(inputHash(dir.path() / "ext.glb"), glb);
}

TEST(InputBinding, MergeRefusesAShardWhoseGlbBufferChanged) {
  TempDir dir("binding_merge");
  const json doc = writeBox(dir.path() / "scenes");
  fs::remove(dir.path() / "scenes" / "box.gltf");
  writeGlb(dir.path() / "scenes" / "box.glb", doc);
  SweepOptions o;
  o.scenes = {dir.path() / "scenes" / "box.glb"};
  o.spp = 2;
  o.width = o.height = 16;
  o.bounces = 1;
  o.threads = 1;
  o.progress = false;
  o.shards = 2;
  o.out = dir.path() / "s0";
  runSweep(o);
  nudgeBuffer(dir.path() / "scenes" / "box.bin");
  o.shard = 1;
  o.out = dir.path() / "s1";
  runSweep(o);
  MergeOptions m;
  m.shards = {dir.path() / "s0", dir.path() / "s1"};
  m.out = dir.path() / "merged";
  EXPECT_ERROR(runMerge(m), "contents of scene");
  EXPECT_FALSE(fs::exists(dir.path() / "merged" / "sweep.json"));
}

TEST(InputBinding, ResumeRefusesTilesTracedFromAnotherBuffer) {
  TempDir dir("binding_resume");
  const json doc = writeBox(dir.path() / "scenes");
  fs::remove(dir.path() / "scenes" / "box.gltf");
  writeGlb(dir.path() / "scenes" / "box.glb", doc);
  SweepOptions o;
  o.scenes = {dir.path() / "scenes" / "box.glb"};
  o.out = dir.path() / "out";
  o.spp = 2;
  o.width = o.height = 16;
  o.threads = 1;
  o.progress = false;
  {
    // The tiles are checkpointed, then writing the outputs fails: the sweep can be resumed.
    const test::ScopedEnv fail("GTBAKE_TEST_FAIL_WRITE", "box.exr");
    EXPECT_ERROR(runSweep(o), "No space left");
  }
  ASSERT_TRUE(fs::exists(o.out / kTileDirectory));
  nudgeBuffer(dir.path() / "scenes" / "box.bin");
  o.resume = true;
  EXPECT_ERROR(runSweep(o), "cannot resume");
  EXPECT_FALSE(fs::exists(o.out / "sweep.json"));
}

TEST(InputBinding, PercentEncodedUrisNameTheirFiles) {
  TempDir dir("binding_uri");
  json doc = writeBox(dir.path());
  const std::string bin = readBytes(dir.path() / "box.bin");
  for (const auto& [uri, file] :
       {std::pair{"my%20buf.bin", "my buf.bin"}, std::pair{"a+b.bin", "a+b.bin"},
        std::pair{"%C3%A9t%C3%A9.bin", "\xC3\xA9t\xC3\xA9.bin"}}) {
    spit(dir.path() / file, bin);
    doc["buffers"][0]["uri"] = uri;
    spit(dir.path() / "uri.gltf", doc.dump());
    EXPECT_EQ(readGltfScene(dir.path() / "uri.gltf").triangles.size(),
              makeClosedBoxScene().triangles.size())
        << uri;
    writeGlb(dir.path() / "uri.glb", doc);
    EXPECT_EQ(readGltfScene(dir.path() / "uri.glb").triangles.size(),
              makeClosedBoxScene().triangles.size())
        << uri;
  }
  // The sweep hashes the files the loader read, so it finds them too.
  doc["buffers"][0]["uri"] = "my%20buf.bin";
  spit(dir.path() / "uri.gltf", doc.dump());
  SweepOptions o;
  o.scenes = {dir.path() / "uri.gltf"};
  o.out = dir.path() / "sweep";
  o.spp = 2;
  o.width = o.height = 8;
  o.threads = 1;
  o.progress = false;
  runSweep(o);
  EXPECT_TRUE(fs::exists(o.out / "uri.exr"));
  // "+" is a literal plus in a uri path, not a space: "a+b.bin" never reads "a b.bin".
  fs::remove(dir.path() / "a+b.bin");
  spit(dir.path() / "a b.bin", bin);
  doc["buffers"][0]["uri"] = "a+b.bin";
  spit(dir.path() / "uri.gltf", doc.dump());
  EXPECT_ERROR(readGltfScene(dir.path() / "uri.gltf"), "uri.gltf");
}

TEST(InputBinding, ImagesAreNeverOpened) {
  TempDir dir("binding_images");
  json doc = writeBox(dir.path());
  const std::string before = inputHash(dir.path() / "box.gltf");
  ASSERT_EQ(::mkfifo((dir.path() / "fifo.png").c_str(), 0600), 0);
  // A 3.9 GB sparse texture: reading it would allocate 3.9 GB.
  sparseFile(dir.path() / "huge.png", 3'900'000'000);
  doc["images"] = {{{"uri", "fifo.png"}}, {{"uri", "huge.png"}}, {{"uri", "missing.png"}}};
  spit(dir.path() / "box.gltf", doc.dump());
  const auto start = std::chrono::steady_clock::now();
  const std::string with_images = inputHash(dir.path() / "box.gltf");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  EXPECT_NE(with_images, before);  // the glTF's own bytes changed
  spit(dir.path() / "huge.png", "other");
  EXPECT_EQ(inputHash(dir.path() / "box.gltf"), with_images);  // images are not scene inputs
}

TEST(InputBinding, BuffersThatAreNotRegularOrTooLargeAreRefusedUnread) {
  TempDir dir("binding_buffers");
  json doc = writeBox(dir.path());
  const std::uint64_t length = doc["buffers"][0]["byteLength"].get<std::uint64_t>();
  auto expectRefused = [&](const std::string& fragment) {
    const auto start = std::chrono::steady_clock::now();
    EXPECT_ERROR(readGltfScene(dir.path() / "box.gltf"), fragment);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  };
  fs::remove(dir.path() / "box.bin");
  sparseFile(dir.path() / "box.bin", 3'900'000'000);
  expectRefused("more than the " + std::to_string(length) + " expected");
  fs::remove(dir.path() / "box.bin");
  ASSERT_EQ(::mkfifo((dir.path() / "box.bin").c_str(), 0600), 0);
  expectRefused("not a regular file");
  fs::remove(dir.path() / "box.bin");
  fs::create_symlink("/dev/zero", dir.path() / "box.bin");
  expectRefused("leaves the glTF's directory");
  fs::remove(dir.path() / "box.bin");
  fs::create_directory(dir.path() / "box.bin");
  expectRefused("box.bin");
}

TEST(InputBinding, NonUtf8SceneFileNamesAreRefusedWithOneLine) {
  TempDir dir("binding_utf8");
  writeGltfScene(dir.path() / "scenes" / "box.gltf", makeClosedBoxScene());
  fs::rename(dir.path() / "scenes" / "box.gltf", dir.path() / "scenes" / "\xff\xfe.gltf");
  SweepOptions o;
  o.scenes = {dir.path() / "scenes"};
  o.out = dir.path() / "out";
  o.spp = 2;
  o.width = o.height = 8;
  o.progress = false;
  EXPECT_ERROR(runSweep(o), "not valid UTF-8");
  EXPECT_FALSE(fs::exists(o.out / "sweep.json"));
}

TEST(ReaderBounds, SetFilesOfAnotherSizeAreRefusedUnread) {
  TempDir dir("set_size");
  spit(dir.path() / "a.dds", "volume");
  const OutputManifest set = sealOutputSet(dir.path(), "encode", {"a.dds"});
  fs::remove(dir.path() / "a.dds");
  sparseFile(dir.path() / "a.dds", 3'900'000'000);  // a 3.9 GB sparse file in its place
  const auto start = std::chrono::steady_clock::now();
  EXPECT_ERROR(set.readVerified("a.dds"), "does not match encode.manifest.json (3900000000 bytes");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  fs::remove(dir.path() / "a.dds");
  ASSERT_EQ(::mkfifo((dir.path() / "a.dds").c_str(), 0600), 0);
  EXPECT_ERROR(set.readVerified("a.dds"), "not a regular file");
}

TEST(ReaderBounds, JsonDepthCannotBeRaisedPastWhatTheParsersSurvive) {
  TempDir dir("json_depth");
  const int ceiling = static_cast<int>(kMaxJsonDepth.ceiling);
  spit(dir.path() / "deep.json", std::string(ceiling, '[') + std::string(ceiling, ']'));
  {
    const test::ScopedEnv env(kMaxJsonDepth.env, std::to_string(ceiling + 1));
    EXPECT_ERROR(readJsonFile(dir.path() / "deep.json"), "must be at most 1000");
  }
  const test::ScopedEnv env(kMaxJsonDepth.env, std::to_string(ceiling));
  const json deep = readJsonFile(dir.path() / "deep.json");
  EXPECT_EQ(deep.dump().size(), 2u * ceiling);
  writeGltfScene(dir.path() / "box.gltf", makeClosedBoxScene());
  json doc = json::parse(readBytes(dir.path() / "box.gltf"));
  doc["extras"] = json::parse(std::string(ceiling - 2, '[') + std::string(ceiling - 2, ']'));
  spit(dir.path() / "box.gltf", doc.dump());
  EXPECT_FALSE(readGltfScene(dir.path() / "box.gltf").triangles.empty());
}

}  // namespace
}  // namespace gtbake
