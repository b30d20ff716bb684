// The reliability rules of docs/limits.md through the real binary: one line on stderr, a non-zero
// exit, nothing written; and the library-level ones (.glb scene directories, holed ground).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <nlohmann/json.hpp>

#include "../cli/cli_harness.h"
#include "common/error.h"
#include "common/output_lock.h"
#include "common/output_set.h"
#include "reliability_util.h"
#include "scene/procedural_scenes.h"
#include "scene/scene.h"
#include "support/test_scenes.h"
#include "sweep/sweep_command.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::readBytes;
using test::spit;
using test::TempDir;

std::size_t lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

void expectOneLineError(const std::string& arguments, const std::string& fragment) {
  const test::RunResult r = test::runGtbake(arguments + " --quiet");
  EXPECT_NE(r.exit_code, 0) << arguments;
  EXPECT_EQ(lines(r.err), 1u) << arguments << "\n" << r.err;
  EXPECT_NE(r.err.find(fragment), std::string::npos) << arguments << "\n" << r.err;
}

// A small committed-style sweep the CLI cases read (two closed boxes, 40x40).
const fs::path& sweepDir() {
  static const TempDir root("cli_sweep");
  static const fs::path dir = [] {
    writeGltfScene(root.path() / "scenes" / "box_a.gltf", makeClosedBoxScene());
    writeGltfScene(root.path() / "scenes" / "box_b.gltf", makeSphericalCavityScene(1.0, 0.7));
    SweepOptions o;
    o.scenes = {root.path() / "scenes"};
    o.out = root.path() / "sweep";
    o.spp = 2;
    o.width = o.height = 40;
    o.bounces = 1;
    o.threads = 1;
    o.progress = false;
    runSweep(o);
    return o.out;
  }();
  return dir;
}

TEST(CliReliability, NonUtf8ArgumentsAreOneLineErrors) {
  TempDir dir("cli_utf8");
  expectOneLineError("sweep --scenes " + (dir.path() / "\xff.gltf").string() + " --out " +
                         (dir.path() / "o").string(),
                     "argument 3 is not valid UTF-8");
  EXPECT_FALSE(fs::exists(dir.path() / "o"));
}

TEST(CliReliability, CostlyGtsoOptionsFailFast) {
  TempDir dir("cli_gtso_cost");
  const std::string out = (dir.path() / "g").string();
  const auto start = std::chrono::steady_clock::now();
  expectOneLineError("gtso --out " + out + " --lobe-cells 1024 --size 4",
                     "GTBAKE_MAX_GTSO_SECONDS");
  expectOneLineError("gtso --out " + out + " --error-lobes 1048576", "GTBAKE_MAX_GTSO_SECONDS");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  EXPECT_FALSE(fs::exists(out));
}

// `gtbake <arguments>` under a 4 GB address-space limit (ulimit -v): its exit status and stderr.
test::RunResult runUnder4GB(const std::string& arguments, const fs::path& dir) {
  const std::string command = "ulimit -v 4000000 && exec " + std::string(GTBAKE_BINARY) + " " +
                              arguments + " </dev/null >/dev/null 2>" + (dir / "err").string();
  const int status = std::system(("sh -c '" + command + "'").c_str());
  test::RunResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = readBytes(dir / "err");
  return r;
}

// Under a 4 GB address-space limit, what the options imply is refused before any work, naming
// the option and the bound (docs/limits.md "Bounded work and memory"): a lobe grid of 1024 cells
// that the time bound lets through (few error lobes) needs 4.8 GB on two threads (it ended in
// std::bad_alloc half a minute in), and a 4096x4096 sweep's views 6.2 GB.
TEST(CliReliability, MemoryTheOptionsImplyIsCheckedAgainstTheAddressSpaceLimit) {
  TempDir dir("cli_memory");
  writeGltfScene(dir.path() / "box.gltf", makeClosedBoxScene());
  const fs::path out = dir.path() / "out";
  const auto start = std::chrono::steady_clock::now();
  const test::RunResult gtso = runUnder4GB(
      "gtso --quiet --size 4 --lobe-cells 1024 --threads 2 --error-lobes 1 --error-seeds 1 "
      "--closed-form-lobes 16 --out " +
          out.string(),
      dir.path());
  const test::RunResult sweep =
      runUnder4GB("sweep --quiet --res 4096x4096 --spp 2 --scenes " +
                      (dir.path() / "box.gltf").string() + " --out " + out.string(),
                  dir.path());
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  const std::string bound = "exceed the address-space limit (ulimit -v) of 4.1 GB";
  for (const auto& [r, option] : {std::pair{&gtso, "gtso --lobe-cells 1024 on 2 threads"},
                                  std::pair{&sweep, "sweep --res 4096x4096"}}) {
    EXPECT_EQ(r->exit_code, 1) << option;
    EXPECT_EQ(lines(r->err), 1u) << r->err;
    EXPECT_NE(r->err.find(option), std::string::npos) << r->err;
    EXPECT_NE(r->err.find(bound), std::string::npos) << r->err;
  }
  EXPECT_FALSE(fs::exists(out));
}

// Two `gtbake export` processes started together into one directory, round after round, with
// 300 files of the user's beside the set so each commit takes a while: whatever the
// interleaving, each run succeeds or is refused with the one-line lock error, one of them
// succeeds, and the directory holds one complete export set, verified against its manifest,
// with the user's files and no leftovers (docs/limits.md "Output sets", "The lock").
TEST(CliReliability, ConcurrentExportsLeaveOneCompleteSet) {
  TempDir dir("cli_export_race");
  const fs::path gtso = dir.path() / "gtso", out = dir.path() / "out";
  ASSERT_EQ(test::runGtbake("gtso --quiet --size 4 --lobe-cells 8 --error-lobes 16 --error-seeds "
                            "1 --closed-form-lobes 64 --threads 1 --out " +
                            gtso.string())
                .exit_code,
            0);
  ASSERT_EQ(test::runGtbake("encode --quiet --threads 1 --gtso " + gtso.string() + " --out " +
                            out.string())
                .exit_code,
            0);
  json fit;
  for (const char* name : {"a1", "a0", "b1", "b0", "c1", "c0"}) {
    fit["linear"][name] = 1.0;
    fit["linear_se"][name] = 0.01;
  }
  fs::create_directories(dir.path() / "fit");
  fs::create_directories(out / "user");
  spit(dir.path() / "fit" / "fit.json", fit.dump());
  sealOutputSet(dir.path() / "fit", "fit", {"fit.json"});
  for (int i = 0; i < 300; ++i) spit(out / "user" / ("note" + std::to_string(i)), "mine");
  const std::string run = std::string(GTBAKE_BINARY) + " export --fit " +
                          (dir.path() / "fit" / "fit.json").string() + " --gtso " + gtso.string() +
                          " --out " + out.string() + " >/dev/null 2>";
  const fs::path err[2] = {dir.path() / "err0", dir.path() / "err1"};
  for (int round = 0; round < 12; ++round) {
    const std::string both = "(" + run + err[0].string() + "; echo $? >" + err[0].string() +
                             ".rc) & (" + run + err[1].string() + "; echo $? >" + err[1].string() +
                             ".rc) & wait";
    ASSERT_EQ(std::system(("sh -c '" + both + "'").c_str()), 0);
    int succeeded = 0;
    for (const fs::path& e : err) {
      const std::string rc = readBytes(e.string() + ".rc"), text = readBytes(e);
      succeeded += rc == "0\n" ? 1 : 0;
      if (rc != "0\n") {
        EXPECT_EQ(rc, "1\n") << text;
        EXPECT_EQ(lines(text), 1u) << text;
        EXPECT_NE(text.find("is being written by another gtbake"), std::string::npos) << text;
      }
    }
    EXPECT_GE(succeeded, 1) << "round " << round;
    verifyOutputSet(readOutputSet(out, "export"));
    verifyOutputSet(readOutputSet(out, "encode"));
    EXPECT_EQ(readBytes(out / "user" / "note299"), "mine");
    EXPECT_EQ(test::gtbakeLeftovers(out), std::vector<std::string>{});
  }
}

TEST(CliReliability, JsonDepthCannotBeRaisedPastItsCeiling) {
  TempDir dir("cli_depth");
  const fs::path sweep = sweepDir();
  const test::ScopedEnv env("GTBAKE_MAX_JSON_DEPTH", "100000");  // the child inherits it
  expectOneLineError(
      "fit --sweep " + sweep.string() + " --out " + (dir.path() / "fit.json").string(),
      "GTBAKE_MAX_JSON_DEPTH must be at most 1000");
}

TEST(CliReliability, SeedsOutsideUint64AreErrorsNotWrapped) {
  TempDir dir("cli_seed");
  const std::string out = (dir.path() / "o").string();
  expectOneLineError("scenes --out " + out + " --seed -1", "--seed must be an integer");
  expectOneLineError("scenes --out " + out + " --seed 18446744073709551616", "--seed must be");
  expectOneLineError("sweep --scenes " + out + " --out " + out + " --seed -1", "--seed must be");
  EXPECT_FALSE(fs::exists(dir.path() / "o"));
}

TEST(CliReliability, EmptyCoeffsAreAnErrorAndShippedIsNamed) {
  expectOneLineError("validate --sweep " + sweepDir().string() + " --coeffs ''",
                     "--coeffs needs six");
  TempDir dir("cli_shipped");
  expectOneLineError("fit --sweep " + sweepDir().string() + " --out " +
                         (dir.path() / "f.json").string() + " --shipped 1,2,3",
                     "--shipped needs six");
  EXPECT_FALSE(fs::exists(dir.path() / "f.json"));
}

TEST(CliReliability, UnknownSubcommandIsNamed) {
  expectOneLineError("bake", "unknown subcommand 'bake'");
}

TEST(CliReliability, SweepNamingAFileSaysSo) {
  TempDir dir("cli_sweepfile");
  expectOneLineError("validate --sweep " + (sweepDir() / "sweep.json").string(), "is a file");
}

TEST(CliReliability, ZeroBouncesAreRefusedBeforeTracing) {
  TempDir dir("cli_bounces");
  expectOneLineError("sweep --scenes " + (sweepDir().parent_path() / "scenes").string() +
                         " --out " + (dir.path() / "o").string() + " --bounces 0",
                     "--bounces 0");
  EXPECT_FALSE(fs::exists(dir.path() / "o"));
}

TEST(CliReliability, FitOutputIsNeverAnInputNorADirectory) {
  const std::string before = readBytes(sweepDir() / "sweep.json");
  expectOneLineError(
      "fit --sweep " + sweepDir().string() + " --out " + (sweepDir() / "sweep.json").string(),
      "would overwrite the input");
  EXPECT_EQ(readBytes(sweepDir() / "sweep.json"), before);
  TempDir dir("cli_fitdir");
  expectOneLineError("fit --sweep " + sweepDir().string() + " --out " + dir.path().string(),
                     "is a directory");
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

// Whatever Ceres or glog would print, a failed fit is one error line (here: too few points).
TEST(CliReliability, FailedFitIsOneLine) {
  TempDir dir("cli_fitfail");
  expectOneLineError(
      "fit --sweep " + sweepDir().string() + " --out " + (dir.path() / "f.json").string(),
      "gtbake: error:");
}

// A binary glTF (one triangle under a camera) assembled by hand: JSON chunk, BIN chunk.
std::string oneTriangleGlb() {
  const float p[9] = {-10, -1, -10, 10, -1, -10, 0, -1, 10};
  std::string bin(reinterpret_cast<const char*>(p), sizeof(p));
  json doc = {
      {"asset", {{"version", "2.0"}}},
      {"buffers", {{{"byteLength", bin.size()}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteLength", bin.size()}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"type", "VEC3"}, {"count", 3}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
      {"cameras", {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}}},
      {"nodes",
       {{{"mesh", 0}},
        {{"camera", 0}, {"rotation", {-0.7071067811865476, 0, 0, 0.7071067811865476}}}}},
      {"scenes", {{{"nodes", {0, 1}}}}}};
  std::string text = doc.dump();
  while (text.size() % 4) text.push_back(' ');
  auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  std::string chunks = u32(static_cast<std::uint32_t>(text.size())) + u32(0x4E4F534A) + text +
                       u32(static_cast<std::uint32_t>(bin.size())) + u32(0x004E4942) + bin;
  return "glTF" + u32(2) + u32(static_cast<std::uint32_t>(12 + chunks.size())) + chunks;
}

TEST(SceneDirectories, GlbFilesAreTakenFromADirectory) {
  TempDir dir("glb_dir");
  fs::create_directories(dir.path() / "scenes");
  spit(dir.path() / "scenes" / "floor.glb", oneTriangleGlb());
  SweepOptions o;
  o.scenes = {dir.path() / "scenes"};
  o.out = dir.path() / "out";
  o.spp = 2;
  o.width = o.height = 8;
  o.bounces = 1;
  o.threads = 1;
  o.progress = false;
  EXPECT_EQ(runSweep(o).views.size(), 1u);
  EXPECT_NE(readOutputSet(o.out, "sweep").find("floor.exr"), nullptr);
}

TEST(SceneDirectories, SweepRefusesASceneWithNoUnmaskedPixel) {
  TempDir dir("no_pixel");
  Scene scene = makeClosedBoxScene();
  scene.camera.position = {1e5, 1e5, 1e5};  // far outside, looking away
  writeGltfScene(dir.path() / "away.gltf", scene);
  SweepOptions o;
  o.scenes = {dir.path() / "away.gltf"};
  o.out = dir.path() / "out";
  o.spp = 2;
  o.width = o.height = 8;
  o.bounces = 1;
  o.threads = 1;
  o.progress = false;
  try {
    runSweep(o);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no pixel sees geometry"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(o.out / "sweep.manifest.json"));
}

// --out naming a FIFO (a directory option or a file option) is one line, and the FIFO stays.
TEST(CliReliability, FifoOutputsAreRefused) {
  TempDir dir("cli_fifo");
  const fs::path fifo = dir.path() / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  expectOneLineError("scenes --classic --out " + fifo.string(), "is a FIFO (named pipe)");
  expectOneLineError("gtso --out " + fifo.string(), "is a FIFO (named pipe)");
  expectOneLineError("fit --sweep " + sweepDir().string() + " --out " + fifo.string(),
                     "is a FIFO (named pipe)");
  EXPECT_EQ(fs::status(fifo).type(), fs::file_type::fifo);
}

// While another process writes a directory, gtbake refuses it with one line naming the directory
// and that pid, and creates nothing.
TEST(CliReliability, ASecondWriterIsRefusedWithOneLine) {
  TempDir dir("cli_locked");
  const fs::path out = dir.path() / "scenes";
  const OutputLock held(out);
  expectOneLineError("scenes --classic --out " + out.string(),
                     out.string() + " is being written by another gtbake (pid " +
                         std::to_string(::getpid()) + ")");
  expectOneLineError("gtso --out " + (out / "gtso").string(), "is being written by another");
  EXPECT_FALSE(fs::exists(out));
}

// A failed `gtbake scenes` (a full disk half-way) leaves the previous corpus whole.
TEST(CliReliability, FailedScenesRunKeepsTheOldCorpus) {
  TempDir dir("cli_scenes_fail");
  const fs::path out = dir.path() / "scenes";
  ASSERT_EQ(test::runGtbake("scenes --classic --quiet --out " + out.string()).exit_code, 0);
  const std::string terrain = readBytes(out / "terrain.bin");
  {
    const test::ScopedEnv fail("GTBAKE_TEST_FAIL_WRITE", "wells");
    expectOneLineError("scenes --classic --seed 7 --out " + out.string(), "No space left");
  }
  verifyOutputSet(readOutputSet(out, "scenes"));
  EXPECT_EQ(readBytes(out / "terrain.bin"), terrain);
}

TEST(SceneDirectories, HoledGroundPreconditionIsAGtbakeError) {
  EXPECT_THROW(makeSphericalCavityScene(1.0, 0.7, 12), Error);
}

}  // namespace
}  // namespace gtbake
