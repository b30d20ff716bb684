// Output sets end to end (docs/limits.md "Output sets"): sweep, fit, gtso and export commit whole
// sets; readers verify them against their manifests and check EXR provenance against sweep.json;
// hostile EXR headers and sweep.json/gtso.json entries are refused before any large allocation.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <nlohmann/json.hpp>
#include <thread>

#include "common/error.h"
#include "common/image_io.h"
#include "common/output_set.h"
#include "encode/encode_command.h"
#include "export/export_command.h"
#include "fit/fit_command.h"
#include "fit/sweep_data.h"
#include "gtso/gtso_command.h"
#include "reliability_fixtures.h"
#include "reliability_util.h"
#include "scene/procedural_scenes.h"
#include "scene/scene.h"
#include "scene/scenes_command.h"
#include "screen_ao/gbuffer.h"
#include "support/test_scenes.h"
#include "sweep/shard_manifest.h"
#include "sweep/sweep_command.h"
#include "validate_gtso/specular_sweep.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::errorOf;
using test::ExportFixture;
using test::readBytes;
using test::ScopedEnv;
using test::spit;
using test::SweepFixture;
using test::TempDir;

const SweepFixture& fixture() {
  static const SweepFixture f;
  return f;
}

fs::path sweepInto(const fs::path& out, std::uint64_t seed = 1, int side = 40) {
  runSweep(fixture().options(out, seed, side));
  return out;
}

TEST(SweepSet, CommittedWithManifestAndVerified) {
  TempDir dir("sweep_set");
  sweepInto(dir.path() / "s");
  const OutputManifest m = readOutputSet(dir.path() / "s", "sweep");
  EXPECT_NE(m.find("sweep.json"), nullptr);
  EXPECT_NE(m.find("box_a.exr"), nullptr);
  EXPECT_NE(m.find("box_b_A.png"), nullptr);
  EXPECT_EQ(m.settings["width"], 40);
  verifyOutputSet(m);
  EXPECT_EQ(loadSweep(dir.path() / "s").scenes.size(), 2u);
}

// A failed rerun (at another resolution) leaves the earlier sweep whole and usable.
TEST(SweepSet, FailedRerunKeepsTheEarlierSweepUsable) {
  TempDir dir("sweep_rerun");
  const fs::path out = sweepInto(dir.path() / "s");
  const std::string before = readBytes(out / "box_a.exr");
  {
    const ScopedEnv fail("GTBAKE_TEST_FAIL_WRITE", "box_b.exr");
    EXPECT_ERROR(sweepInto(out, 1, 48), "No space left");
  }
  EXPECT_EQ(readBytes(out / "box_a.exr"), before);
  EXPECT_EQ(loadSweep(out).points(), 2u * 40 * 40);
  for (const auto& e : fs::directory_iterator(out)) {
    EXPECT_EQ(e.path().string().find(".gtbake-"), std::string::npos) << e.path();
  }
}

TEST(SweepSet, ReadersRefuseMixedSeedsDuplicatesAndForeignScenes) {
  TempDir dir("sweep_mix");
  const fs::path one = sweepInto(dir.path() / "seed1");
  const fs::path two = sweepInto(dir.path() / "seed2", 2);
  // A file from another run, dropped in: the manifest catches it.
  fs::copy_file(two / "box_a.exr", one / "box_a.exr", fs::copy_options::overwrite_existing);
  EXPECT_ERROR(loadSweep(one), "does not match sweep.manifest.json");
  // Even resealed, its attributes give it away.
  resealOutputSet(one, "sweep");
  EXPECT_ERROR(loadSweep(one), "gtbake.seed");
  // The EXR of another scene under this scene's name.
  const fs::path three = sweepInto(dir.path() / "swap");
  fs::copy_file(three / "box_b.exr", three / "box_a.exr", fs::copy_options::overwrite_existing);
  resealOutputSet(three, "sweep");
  EXPECT_ERROR(loadSweep(three), "gtbake.scene");
  // The same scene listed twice.
  const fs::path four = sweepInto(dir.path() / "dup");
  json doc = json::parse(readBytes(four / "sweep.json"));
  doc["views"][1] = doc["views"][0];
  spit(four / "sweep.json", doc.dump());
  resealOutputSet(four, "sweep");
  EXPECT_ERROR(loadSweep(four), "listed twice");
  // No manifest at all (an interrupted commit, or files from elsewhere).
  fs::remove(four / "sweep.manifest.json");
  EXPECT_ERROR(loadSweep(four), "rerun `gtbake sweep`");
}

// Two images of one name (or one file under two names), the manifest resealed: every reader of a
// sweep set refuses it with one line before decoding an image, instead of an internal "written
// twice" after all its work (fit, screen-ao and tune, validate-gtso, merge's shards).
TEST(SweepSet, EveryReaderRefusesANameOrFileListedTwice) {
  TempDir dir("sweep_twice");
  SweepOptions o = fixture().options(dir.path() / "s", 1, 16);
  o.specular_roughness = {0.4};
  o.specular_spp = 2;
  runSweep(o);
  o.shards = 2;
  o.out = dir.path() / "shard";
  runSweep(o);
  const std::string good = readBytes(o.out.parent_path() / "s" / "sweep.json");
  for (const char* key : {"name", "file"}) {
    json doc = json::parse(good);
    doc["views"][1][key] = doc["views"][0][key];
    spit(dir.path() / "s" / "sweep.json", doc.dump());
    resealOutputSet(dir.path() / "s", "sweep");
    const std::string twice = "view '" + doc["views"][1]["name"].get<std::string>() + "' (" +
                              doc["views"][1]["file"].get<std::string>() + ") is listed twice";
    EXPECT_ERROR(loadSweep(dir.path() / "s"), twice);
    EXPECT_ERROR(readSweepImages(dir.path() / "s"), twice);
    EXPECT_ERROR(readSpecularSweep(dir.path() / "s"), twice);
  }
  json shard = json::parse(readBytes(o.out / "shard.json"));
  shard["views"][1]["name"] = shard["views"][0]["name"];
  spit(o.out / "shard.json", shard.dump());
  resealOutputSet(o.out, kShardSet);
  EXPECT_ERROR(readShardManifest(o.out), "view 'box_a' is listed twice");
}

// A sweep or shard of the older layout, whose per-view list was named "scenes" (docs/scenes.md
// "Vocabulary"), resealed so only the layout differs: every reader refuses it with one line that
// says to trace it again, rather than reading it.
TEST(SweepSet, EveryReaderRefusesTheOlderLayoutWithScenes) {
  TempDir dir("sweep_old_layout");
  SweepOptions o = fixture().options(dir.path() / "s", 1, 16);
  o.specular_roughness = {0.4};
  o.specular_spp = 2;
  runSweep(o);
  json doc = json::parse(readBytes(o.out / "sweep.json"));
  doc["scenes"] = doc["views"];
  doc.erase("views");
  spit(o.out / "sweep.json", doc.dump());
  resealOutputSet(o.out, "sweep");
  const std::string rerun = "an older layout that this gtbake does not read: re-run `gtbake sweep`";
  EXPECT_ERROR(loadSweep(o.out), rerun);
  EXPECT_ERROR(readSweepImages(o.out), rerun);
  EXPECT_ERROR(readSpecularSweep(o.out), rerun);
  o.shards = 2;
  o.out = dir.path() / "shard";
  runSweep(o);
  json shard = json::parse(readBytes(o.out / "shard.json"));
  shard["format"] = "gtbake-shard 1";
  shard["scenes"] = shard["views"];
  shard.erase("views");
  spit(o.out / "shard.json", shard.dump());
  resealOutputSet(o.out, kShardSet);
  EXPECT_ERROR(readShardManifest(o.out), "shard.json is not a gtbake-shard 2 record");
}

TEST(SweepSet, HostileSweepJsonEntries) {
  TempDir dir("sweep_json");
  const fs::path out = sweepInto(dir.path() / "s");
  const std::string good = readBytes(out / "sweep.json");
  auto edited = [&](const std::function<void(json&)>& edit) {
    json doc = json::parse(good);
    edit(doc);
    spit(out / "sweep.json", doc.dump());
    resealOutputSet(out, "sweep");
  };
  // get<int>() used to truncate 2^32 + 2 to 2.
  edited([](json& d) { d["settings"]["spp"] = 4294967298ull; });
  EXPECT_ERROR(loadSweep(out), "'spp' must be an integer in");
  edited([](json& d) { d["views"][0]["file"] = "../s/box_a.exr"; });
  EXPECT_ERROR(loadSweep(out), "'..' is not allowed");
  edited([&](json& d) { d["views"][0]["file"] = (fs::absolute(out) / "box_a.exr").string(); });
  EXPECT_ERROR(loadSweep(out), "must be a relative path");
  edited([](json& d) { d["views"][0]["width"] = 4000000000ull; });
  EXPECT_ERROR(loadSweep(out), "'width' must be an integer");
  spit(out / "sweep.json", std::string(5000, '[') + std::string(5000, ']'));
  resealOutputSet(out, "sweep");
  EXPECT_ERROR(loadSweep(out), "GTBAKE_MAX_JSON_DEPTH");
}

// Finds the int32 fields of the header's "dataWindow" box2i (xMin, yMin, xMax, yMax).
std::size_t dataWindowOffset(const std::string& exr) {
  const std::string key("dataWindow\0box2i\0", 17);
  const std::size_t at = exr.find(key);
  EXPECT_NE(at, std::string::npos);
  return at + key.size() + 4;  // skip the attribute size
}

TEST(ExrHostile, ForgedDataWindowIsRefusedBeforeAllocating) {
  const std::vector<ExrChannel> channels = {{"A", std::vector<float>(16 * 16, 0.5f)},
                                            {"mask", std::vector<float>(16 * 16, 1.0f)}};
  const std::string good = encodeExr(16, 16, channels);
  EXPECT_EQ(decodeExr(good, "good.exr").width, 16);
  auto forged = [&](std::int32_t x_max, std::int32_t y_max, std::int32_t x_min = 0) {
    std::string bytes = good;
    const std::size_t at = dataWindowOffset(bytes);
    std::memcpy(&bytes[at], &x_min, 4);
    std::memcpy(&bytes[at + 8], &x_max, 4);
    std::memcpy(&bytes[at + 12], &y_max, 4);
    return bytes;
  };
  // 5 GB of floats from a ~1 KB file: refused by the size the file could hold.
  // (OpenEXR may already fail on the missing line offsets; either way nothing large is made.)
  const std::string large = errorOf([&] { decodeExr(forged(8000, 8000), "f.exr"); });
  EXPECT_TRUE(large.find("far larger") != std::string::npos ||
              large.find("cannot read EXR") != std::string::npos)
      << large;
  // Beyond the largest side any sweep writes: refused while the header is read.
  EXPECT_ERROR(decodeExr(forged(200000, 200000), "f.exr"), "cannot read EXR");
  EXPECT_ERROR(decodeExr(forged(15, 15, -10), "f.exr"), "EXR");
  // A size other than the provenance says, before any pixel is read.
  EXPECT_ERROR(decodeExr(good, "g.exr", {32, 16, "sweep.json"}), "does not match sweep.json");
  EXPECT_ERROR(decodeExr(good.substr(0, good.size() / 2), "t.exr"), "cannot read EXR");
  // An attribute whose stated size exceeds the file (OpenEXR would allocate it), and a channel
  // list whose entries disagree with its stated size (found by fuzz_exr: OpenEXR then parsed the
  // rest of the header from another offset and allocated gigabytes).
  {
    std::string bytes = good;
    const std::size_t at = bytes.find(std::string("channels\0chlist\0", 16)) + 16;
    const std::int32_t huge = 1 << 30;
    std::memcpy(&bytes[at], &huge, 4);
    EXPECT_ERROR(decodeExr(bytes, "h.exr"), "more than the file holds");
    std::int32_t off_by_two = 0;
    std::memcpy(&off_by_two, &good[at], 4);
    off_by_two -= 2;
    std::memcpy(&bytes[at], &off_by_two, 4);
    EXPECT_ERROR(decodeExr(bytes, "c.exr"), "malformed channel list");
  }
  EXPECT_ERROR(decodeExr("", "e.exr"), "cannot read EXR");
}

// The in-memory reader against a closed form: every pixel and attribute comes back exactly, and
// a file cut anywhere is refused with one error line (the reader reads past the end of the bytes
// it was given, or seeks there, only to fail).
TEST(ExrRead, DecodesEveryPixelAndRefusesEveryTruncation) {
  std::vector<ExrChannel> channels = {{"A", {}}, {"B", {}}};
  for (int p = 0; p < 24 * 10; ++p) {
    channels[0].pixels.push_back(static_cast<float>(p) / 7.0f);
    channels[1].pixels.push_back(-static_cast<float>(p * p));
  }
  const std::string good = encodeExr(24, 10, channels, {{"gtbake.spp", "16"}});
  const ExrImage image = decodeExr(good, "good.exr");
  EXPECT_EQ(image.width, 24);
  EXPECT_EQ(image.height, 10);
  EXPECT_EQ(image.channel("A", "good.exr"), channels[0].pixels);
  EXPECT_EQ(image.channel("B", "good.exr"), channels[1].pixels);
  EXPECT_EQ(image.attributes.at("gtbake.spp"), "16");
  for (std::size_t cut = 0; cut < good.size(); cut += 1 + good.size() / 61) {
    const std::string what = errorOf([&] { decodeExr(good.substr(0, cut), "cut.exr"); });
    EXPECT_EQ(what.rfind("cannot read EXR cut.exr: ", 0), 0u) << cut << ": " << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

// readVerifiedExr keys its decoded image by the manifest's SHA-256 instead of hashing the bytes
// again, and still verifies every read: an image decoded before is shared (not copied) only
// while the file still matches its manifest; an edited file is refused even though its old image
// is kept (docs/limits.md §Output sets).
TEST(ExrRead, AVerifiedReadRefusesAnEditedFileWhoseImageIsKept) {
  TempDir dir("exr_verified");
  std::vector<ExrChannel> channels = {{"A", std::vector<float>(16 * 16)}};
  for (std::size_t p = 0; p < channels[0].pixels.size(); ++p) {
    channels[0].pixels[p] = 0.25f + static_cast<float>(p % 13);
  }
  const std::string bytes = encodeExr(16, 16, channels);
  for (const char* set_dir : {"one", "two"}) {
    OutputSet set(dir.path() / set_dir, "demo");
    set.add("a.exr", bytes);
    set.commit();
  }
  const OutputManifest one = readOutputSet(dir.path() / "one", "demo");
  const OutputManifest two = readOutputSet(dir.path() / "two", "demo");
  const std::shared_ptr<const ExrImage> first = readVerifiedExr(one, "a.exr", "one/a.exr");
  EXPECT_EQ(first->channel("A", "a.exr"), channels[0].pixels);
  // The same bytes, read again or from another set, give the image already decoded; decodeExr,
  // which hashes the bytes itself, finds the same key and the same pixels.
  EXPECT_EQ(readVerifiedExr(one, "a.exr", "one/a.exr").get(), first.get());
  EXPECT_EQ(readVerifiedExr(two, "a.exr", "two/a.exr").get(), first.get());
  EXPECT_EQ(decodeExr(bytes, "a.exr").channels, first->channels);
  EXPECT_ERROR(readVerifiedExr(one, "a.exr", "one/a.exr", {16, 32, "sweep.json"}),
               "does not match sweep.json");
  // One byte of the pixel data changed, same size: refused, though its old image is kept.
  std::string edited = bytes;
  edited[edited.size() - 5] ^= 0x20;
  spit(dir.path() / "one" / "a.exr", edited);
  EXPECT_ERROR(readVerifiedExr(one, "a.exr", "one/a.exr"), "does not match demo.manifest.json");
  // Another valid EXR in its place: refused too.
  channels[0].pixels[0] = 9.0f;
  spit(dir.path() / "one" / "a.exr", encodeExr(16, 16, channels));
  EXPECT_ERROR(readVerifiedExr(one, "a.exr", "one/a.exr"), "does not match demo.manifest.json");
  EXPECT_ERROR(readVerifiedExr(one, "b.exr", "one/b.exr"), "is not part of the output set");
  // The untouched copy still reads.
  EXPECT_EQ(readVerifiedExr(two, "a.exr", "two/a.exr").get(), first.get());
}

// A verified file whose identity (device, inode, size, modification and status-change times) is
// unchanged and was settled when it was read is not read again; any write in place, even one that
// restores the same bytes and size, changes the identity and the file is read and verified again,
// and a file read while still fresh is never taken as unchanged.
TEST(ExrRead, AnUnchangedSettledFileIsNotReadAgainAndAnyWriteIsSeen) {
  TempDir dir("exr_unchanged");
  std::vector<ExrChannel> channels = {{"A", std::vector<float>(8 * 8)}};
  for (std::size_t p = 0; p < channels[0].pixels.size(); ++p) {
    channels[0].pixels[p] = 1.5f + static_cast<float>(p % 7);
  }
  const std::string bytes = encodeExr(8, 8, channels);
  for (const char* set_dir : {"settled", "fresh"}) {
    OutputSet set(dir.path() / set_dir, "demo");
    set.add("a.exr", bytes);
    set.commit();
    if (std::string(set_dir) == "settled") std::this_thread::sleep_for(std::chrono::seconds(2));
  }
  const OutputManifest settled = readOutputSet(dir.path() / "settled", "demo");
  const OutputManifest fresh = readOutputSet(dir.path() / "fresh", "demo");
  auto delta = [](const ExrReadCounts& from) {
    const ExrReadCounts now = exrReadCounts();
    return std::make_pair(now.read - from.read, now.unchanged - from.unchanged);
  };
  using Counts = std::pair<std::size_t, std::size_t>;
  ExrReadCounts start = exrReadCounts();
  const std::shared_ptr<const ExrImage> first = readVerifiedExr(settled, "a.exr", "a.exr");
  EXPECT_EQ(readVerifiedExr(settled, "a.exr", "a.exr").get(), first.get());
  EXPECT_EQ(delta(start), Counts(1, 1));
  EXPECT_ERROR(readVerifiedExr(settled, "a.exr", "a.exr", {8, 16, "sweep.json"}),
               "does not match sweep.json");
  // The file just written (the second set, committed a moment ago) is read every time.
  start = exrReadCounts();
  readVerifiedExr(fresh, "a.exr", "a.exr");
  readVerifiedExr(fresh, "a.exr", "a.exr");
  EXPECT_EQ(delta(start), Counts(2, 0));
  // A byte changed in place, same size: the write is seen and the file refused.
  std::string edited = bytes;
  edited[edited.size() - 5] ^= 0x20;
  const fs::path path = dir.path() / "settled" / "a.exr";
  spit(path, edited);
  start = exrReadCounts();
  EXPECT_ERROR(readVerifiedExr(settled, "a.exr", "a.exr"), "does not match demo.manifest.json");
  // The original bytes written back: read and verified again (the write left a fresh identity).
  spit(path, bytes);
  EXPECT_EQ(readVerifiedExr(settled, "a.exr", "a.exr").get(), first.get());
  EXPECT_EQ(readVerifiedExr(settled, "a.exr", "a.exr").get(), first.get());
  EXPECT_EQ(delta(start), Counts(2, 0));
}

TEST(FitSet, OutputNeverReplacesAnInputAndIsNeverADirectory) {
  TempDir dir("fit_out");
  // 16 walks per pixel: enough distinct A values for the cubic to be determined.
  SweepOptions so = fixture().options(dir.path() / "s");
  so.spp = 16;
  runSweep(so);
  const fs::path sweep = so.out;
  const std::string before = readBytes(sweep / "sweep.json");
  FitOptions o;
  o.sweep = sweep;
  o.progress = false;
  o.out = sweep / "sweep.json";
  EXPECT_ERROR(runFit(o), "would overwrite the input");
  o.out = sweep / "." / "box_a.exr";
  EXPECT_ERROR(runFit(o), "would overwrite the input");
  EXPECT_EQ(readBytes(sweep / "sweep.json"), before);
  fs::create_directories(dir.path() / "adir");
  o.out = dir.path() / "adir";
  EXPECT_ERROR(runFit(o), "is a directory");
  EXPECT_TRUE(fs::is_empty(dir.path() / "adir"));
  // Beside the sweep is fine (the flat layout of older gtbake wrote luts/fit.json there).
  o.out = sweep / "fit.json";
  o.report = dir.path() / "report";
  runFit(o);
  EXPECT_EQ(readOutputSet(sweep, "fit").readVerified("fit.json"), readBytes(sweep / "fit.json"));
}

// With encode's volumes in another directory (encode/ beside ship/, docs/reproducibility.md
// "Layout") export ships them too: each volume byte for byte, verified, and a README naming them.
TEST(ExportSet, ShipsTheVolumesOfAnotherEncodeDirectory) {
  const ExportFixture f;
  const fs::path encode = f.root.path() / "encode", ship = f.root.path() / "ship";
  f.encode(encode);
  ExportOptions e = f.options(ship);
  e.encode = encode;
  runExport(e);
  const OutputManifest volumes = readOutputSet(encode, "encode");
  const OutputManifest shipped = readOutputSet(ship, "export");
  EXPECT_EQ(shipped.files.size(), 4u + 12u);  // header, 2 includes, README.md, 12 volumes
  for (const OutputFile& v : volumes.files) {
    if (v.name == "encode.json") continue;
    ASSERT_NE(shipped.find(v.name), nullptr) << v.name;
    EXPECT_EQ(shipped.find(v.name)->sha256, v.sha256) << v.name;
  }
  EXPECT_NE(shipped.readVerified("README.md").find("`gtso4d.ktx2`"), std::string::npos);
  // A volume edited after encode is refused, not shipped.
  spit(encode / "gtso3d_r8.dds", "edited");
  EXPECT_ERROR(runExport(e), "gtso3d_r8.dds");
}

TEST(ExportSet, FailedExportLeavesNoNewFileBesideOldOnes) {
  const ExportFixture f;
  const fs::path out = f.root.path() / "export";
  f.encode(out);
  // 2 tables x {BC4, R16, R8} x {DDS, KTX2} + encode.json (layouts)
  EXPECT_EQ(readOutputSet(out, "encode").files.size(), 13u);
  runExport(f.options(out));
  const OutputManifest m = readOutputSet(out, "export");
  EXPECT_EQ(m.files.size(), 4u);  // header + 2 includes + README.md
  const std::string header = readBytes(out / "gtbake_tables.h");
  // Change the inputs, then fail half-way through writing: nothing of the new set appears.
  json g = json::parse(readBytes(f.gtso / "gtso.json"));
  g["cone"]["u"] = 0.5;
  spit(f.gtso / "gtso.json", g.dump());
  resealOutputSet(f.gtso, "gtso");
  {
    const ScopedEnv fail("GTBAKE_TEST_FAIL_WRITE", "gtbake_tables.glsl");
    EXPECT_ERROR(runExport(f.options(out)), "No space left");
  }
  EXPECT_EQ(readBytes(out / "gtbake_tables.h"), header);
  verifyOutputSet(readOutputSet(out, "export"));
}

TEST(ExportSet, InputsAreVerifiedAndBounded) {
  const ExportFixture f;
  const fs::path out = f.root.path() / "export";
  // A table edited after gtso wrote it.
  const std::string table = readBytes(f.gtso / "gtso3d.f32");
  spit(f.gtso / "gtso3d.f32", table.substr(0, table.size() - 4) + std::string(4, '\0'));
  EXPECT_ERROR(runExport(f.options(out)), "does not match gtso.manifest.json");
  spit(f.gtso / "gtso3d.f32", table);
  const std::string good = readBytes(f.gtso / "gtso.json");
  auto edited = [&](const std::function<void(json&)>& edit) {
    json doc = json::parse(good);
    edit(doc);
    spit(f.gtso / "gtso.json", doc.dump());
    resealOutputSet(f.gtso, "gtso");
  };
  edited([](json& d) { d["tables"]["3d"]["file"] = "../fit/fit.json"; });
  EXPECT_ERROR(runExport(f.options(out)), "must be a plain file name");
  edited([](json& d) { d["tables"]["4d"]["dims"] = {4096, 4096, 4096, 4096}; });
  EXPECT_ERROR(runExport(f.options(out)), "GTBAKE_MAX_INPUT_BYTES");
  edited([](json& d) { d["tables"]["3d"]["dims"] = {4294967300ull, 4, 4}; });
  EXPECT_ERROR(runExport(f.options(out)), "integer in [2, 4096]");
  // fit.json without its manifest.
  fs::remove(f.fit.parent_path() / "fit.manifest.json");
  EXPECT_ERROR(runExport(f.options(out)), "rerun `gtbake fit`");
  EXPECT_FALSE(fs::exists(out));
}

TEST(GtsoBounds, SamplesAndSizeAreBoundedBeforeWork) {
  TempDir dir("gtso_bounds");
  GtsoOptions g;
  g.out = dir.path() / "g";
  g.progress = false;
  g.lobe_cells = 2000000000;
  EXPECT_ERROR(runGtso(g), "--lobe-cells must be");
  g.lobe_cells = 0;
  g.closed_form_lobes = 8;
  EXPECT_ERROR(runGtso(g), "--closed-form-lobes must be");
  g.closed_form_lobes = 0;
  g.size = 6;  // export's BC4 blocks need multiples of 4
  EXPECT_ERROR(runGtso(g), "multiple of 4");
  g.size = 256;
  EXPECT_ERROR(runGtso(g), "GTBAKE_MAX_GTSO_SECONDS");
  // Small tables with a huge lobe grid or error set cost what the lobes cost, not size^4.
  g.size = 4;
  g.lobe_cells = 1024;
  EXPECT_ERROR(runGtso(g), "GTBAKE_MAX_GTSO_SECONDS");
  g.lobe_cells = 0;
  g.error_lobes = 1 << 20;
  EXPECT_ERROR(runGtso(g), "GTBAKE_MAX_GTSO_SECONDS");
  EXPECT_FALSE(fs::exists(g.out));
}

// The memory the options imply is checked before any work (docs/limits.md "Bounded work and
// memory"): lobe grids of 4096 cells (the texel check's 4x of --lobe-cells 1024) on two threads
// need 4.8 GB, and 2^20 error lobes over 64 seeds 161 GB of points; each names its options.
TEST(GtsoBounds, MemoryOfTheLobeGridsAndPointsIsBoundedBeforeWork) {
  TempDir dir("gtso_memory");
  const ScopedEnv seconds("GTBAKE_MAX_GTSO_SECONDS", "1000000000");
  const ScopedEnv bytes("GTBAKE_MAX_GTSO_BYTES", "4000000000");
  GtsoOptions g;
  g.out = dir.path() / "g";
  g.progress = false;
  g.size = 4;
  g.lobe_cells = 1024;
  g.threads = 2;
  g.error_lobes = 1;
  g.error_seeds = 1;
  g.closed_form_lobes = 16;
  const auto start = std::chrono::steady_clock::now();
  const std::string message = errorOf([&] { runGtso(g); });
  EXPECT_NE(message.find("gtso --lobe-cells 1024 on 2 threads"), std::string::npos) << message;
  EXPECT_NE(message.find("GTBAKE_MAX_GTSO_BYTES"), std::string::npos) << message;
  g.lobe_cells = 0;
  g.error_lobes = 1 << 20;
  g.error_seeds = 64;
  EXPECT_ERROR(runGtso(g), "gtso --error-lobes 1048576 --error-seeds 64 (the end-to-end points)");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  EXPECT_FALSE(fs::exists(g.out));
}

// A failed run (a full disk on the last buffer) leaves the previous corpus whole: every file of
// it, the seeded clutter and terrain included, matches its manifest, and no new file appears.
TEST(ScenesWrite, InjectedFailureLeavesTheOldCorpusWhole) {
  TempDir dir("scenes_fail");
  runScenes({dir.path(), 1, false, true});
  const OutputManifest before = readOutputSet(dir.path(), "scenes");
  std::vector<std::string> bytes;
  for (const OutputFile& f : before.files) bytes.push_back(readBytes(dir.path() / f.name));
  const ScopedEnv fail("GTBAKE_TEST_FAIL_WRITE", "wells.bin");
  EXPECT_ERROR(runScenes({dir.path(), 2, false, true}), "No space left");
  const OutputManifest after = readOutputSet(dir.path(), "scenes");
  verifyOutputSet(after);
  ASSERT_EQ(after.files.size(), before.files.size());
  for (std::size_t k = 0; k < before.files.size(); ++k) {
    EXPECT_EQ(readBytes(dir.path() / before.files[k].name), bytes[k]) << before.files[k].name;
  }
  EXPECT_EQ(after.settings["seed"], 1);
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir.path())) entries += e.exists() ? 1 : 0;
  EXPECT_EQ(entries, before.files.size() + 1);  // the files and the manifest, nothing else
}

TEST(ScenesWrite, StaleTemporariesOfAKilledRunAreRemoved) {
  TempDir dir("scenes_stale");
  const pid_t child = ::fork();
  if (child == 0) std::_Exit(0);
  ::waitpid(child, nullptr, 0);
  const fs::path stale = dir.path() / ("cavity.gltf.gtbake-tmp-" + std::to_string(child));
  spit(stale, "{");
  spit(dir.path() / "thesis.tmp-4242", "the user's");
  runScenes({dir.path(), 1, false, true});
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_EQ(readBytes(dir.path() / "thesis.tmp-4242"), "the user's");
}

TEST(ScenesWrite, FullTmpfsIsAnError) {
  TempDir dir("scenes_tmpfs");
  const fs::path mount = dir.path() / "mnt";
  fs::create_directories(mount);
  const std::string cmd = "mount -t tmpfs -o size=256k tmpfs " + mount.string() + " 2>/dev/null";
  if (std::system(cmd.c_str()) != 0) GTEST_SKIP() << "cannot mount a tmpfs here";
  struct Unmount {
    fs::path p;
    ~Unmount() { (void)!std::system(("umount " + p.string()).c_str()); }
  } unmount{mount};
  EXPECT_ERROR(runScenes({mount / "scenes", 1, false, true}), "cannot write");
  for (const auto& e : fs::recursive_directory_iterator(mount)) {
    EXPECT_EQ(e.path().string().find(".gtbake-"), std::string::npos) << e.path();
    EXPECT_FALSE(e.is_regular_file()) << e.path();  // nothing half-written is left
  }
}

}  // namespace
}  // namespace gtbake
