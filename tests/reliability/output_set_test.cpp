// Output sets, the checked writer, SHA-256 and the stale-temporary cleanup (src/common).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_set.h"
#include "common/sha256.h"
#include "reliability_util.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using test::readBytes;
using test::ScopedEnv;
using test::spit;
using test::TempDir;

// FIPS 180-4 / NIST CAVS example digests, including the 55/56/64-byte padding boundaries.
TEST(Sha256, KnownVectors) {
  EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256Hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  EXPECT_EQ(sha256Hex(std::string(64, 'a')),
            "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb");
}

TEST(OutputSet, CommitWritesFilesThenManifestAndReadersVerify) {
  TempDir dir("set_commit");
  {
    OutputSet set(dir.path(), "demo");
    set.add("a.txt", "alpha");
    set.add("sub/b.bin", std::string("\0\1\2", 3));
    set.setSettings({{"spp", 4}});
    // Nothing final exists before commit.
    EXPECT_FALSE(fs::exists(dir.path() / "a.txt"));
    EXPECT_FALSE(fs::exists(dir.path() / "demo.manifest.json"));
    set.commit();
  }
  const OutputManifest m = readOutputSet(dir.path(), "demo");
  ASSERT_EQ(m.files.size(), 2u);
  EXPECT_EQ(m.settings["spp"], 4);
  EXPECT_EQ(m.readVerified("a.txt"), "alpha");
  verifyOutputSet(m);
  // A file edited after the run is caught.
  spit(dir.path() / "a.txt", "alphA");
  EXPECT_THROW(m.readVerified("a.txt"), Error);
  // Not part of the set.
  EXPECT_THROW(m.verify("c.txt", "x"), Error);
  // Another command's manifest is refused.
  EXPECT_THROW(readOutputSet(dir.path(), "other"), Error);
}

TEST(OutputSet, FailedRunLeavesThePreviousSetValid) {
  TempDir dir("set_fail");
  {
    OutputSet set(dir.path(), "demo");
    set.add("a.txt", "old");
    set.commit();
  }
  try {
    OutputSet set(dir.path(), "demo");
    set.add("a.txt", "new");
    throw Error("stage failed");  // before commit
  } catch (const Error&) {
  }
  const OutputManifest m = readOutputSet(dir.path(), "demo");
  EXPECT_EQ(m.readVerified("a.txt"), "old");
  for (const auto& e : fs::directory_iterator(dir.path())) {
    EXPECT_EQ(e.path().string().find(".tmp-"), std::string::npos) << e.path();
  }
}

TEST(OutputSet, InjectedWriteFailureThrowsAndKeepsOldSet) {
  TempDir dir("set_inject");
  {
    OutputSet set(dir.path(), "demo");
    set.add("big.bin", std::string(100000, 'x'));
    set.commit();
  }
  {
    const ScopedEnv fail("GTBAKE_TEST_FAIL_WRITE", "big.bin");
    OutputSet set(dir.path(), "demo");
    try {
      set.add("big.bin", std::string(100000, 'y'));
      FAIL() << "the injected failure was not reported";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("No space left"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(readOutputSet(dir.path(), "demo").readVerified("big.bin"), std::string(100000, 'x'));
}

TEST(OutputSet, RefusesNamesOutsideTheDirectoryAndUnsafeManifests) {
  TempDir dir("set_names");
  OutputSet set(dir.path(), "demo");
  EXPECT_THROW(set.add("../escape.txt", "x"), Error);
  EXPECT_THROW(set.add("/tmp/abs.txt", "x"), Error);
  EXPECT_THROW(set.add("%2e%2e/escape.txt", "x"), Error);
  spit(dir.path() / "evil.manifest.json",
       R"({"command":"evil","gtbake_version":"0","files":[{"name":"../x","size":1,)"
       R"("sha256":"0000000000000000000000000000000000000000000000000000000000000000"}]})");
  EXPECT_THROW(readOutputSet(dir.path(), "evil"), Error);
  EXPECT_THROW(readOutputSet(dir.path(), "missing"), Error);
}

// A file on a full file system: if a small tmpfs can be mounted here, fill it for real.
TEST(CheckedWriter, FullTmpfsIsAnErrorAndLeavesTheOldFile) {
  TempDir dir("tmpfs");
  const fs::path mount = dir.path() / "mnt";
  fs::create_directories(mount);
  const std::string cmd = "mount -t tmpfs -o size=64k tmpfs " + mount.string() + " 2>/dev/null";
  if (std::system(cmd.c_str()) != 0) GTEST_SKIP() << "cannot mount a tmpfs here";
  struct Unmount {
    fs::path p;
    ~Unmount() { std::system(("umount " + p.string()).c_str()); }
  } unmount{mount};
  writeFileAtomically(mount / "keep.bin", "good");
  EXPECT_THROW(writeFileAtomically(mount / "keep.bin", std::string(1 << 20, 'z')), Error);
  EXPECT_EQ(readBytes(mount / "keep.bin"), "good");
  EXPECT_FALSE(fs::exists(mount / ("keep.bin.tmp-" + std::to_string(::getpid()))));
}

TEST(CheckedWriter, InjectedFailureNeverReplacesTheOldFile) {
  TempDir dir("inject");
  writeFileAtomically(dir.path() / "f.json", "old");
  const ScopedEnv fail("GTBAKE_TEST_FAIL_WRITE", "f.json");
  EXPECT_THROW(writeFileAtomically(dir.path() / "f.json", "new contents"), Error);
  EXPECT_EQ(readBytes(dir.path() / "f.json"), "old");
}

// A child killed by SIGTERM while its temporary file exists leaves nothing behind.
TEST(Signals, TermRemovesTheTemporaryFiles) {
  TempDir dir("signal");
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  if (child == 0) {
    OutputSet set(dir.path(), "demo");
    set.add("a.bin", "staged");
    const char byte = 1;
    (void)!::write(ready[1], &byte, 1);
    ::pause();
    std::_Exit(0);
  }
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  EXPECT_TRUE(fs::exists(dir.path() / ("a.bin.tmp-" + std::to_string(child))));
  ::kill(child, SIGTERM);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  EXPECT_FALSE(fs::exists(dir.path() / ("a.bin.tmp-" + std::to_string(child))));
  ::close(ready[0]);
  ::close(ready[1]);
}

// SIGKILL cannot be caught: the next run removes what the killed one left.
TEST(Signals, StaleTemporariesOfADeadProcessAreCleanedNextRun) {
  TempDir dir("stale");
  const pid_t child = ::fork();
  if (child == 0) std::_Exit(0);
  ::waitpid(child, nullptr, 0);  // a pid that no longer runs
  const fs::path stale = dir.path() / ("sweep.json.tmp-" + std::to_string(child));
  spit(stale, "half");
  const fs::path live = dir.path() / ("x.tmp-" + std::to_string(::getppid()));
  spit(live, "parent's");
  const auto removed = cleanStaleTemporaries(dir.path());
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
}

TEST(OutputPaths, SameOrInside) {
  TempDir dir("same");
  spit(dir.path() / "sweep.json", "{}");
  EXPECT_TRUE(sameOrInside(dir.path() / "sweep.json", dir.path() / "sweep.json"));
  EXPECT_TRUE(sameOrInside(dir.path() / "." / "sweep.json", dir.path() / "sweep.json"));
  EXPECT_TRUE(sameOrInside(dir.path(), dir.path() / "sweep.json"));
  EXPECT_FALSE(sameOrInside(dir.path() / "fit.json", dir.path() / "sweep.json"));
}

}  // namespace
}  // namespace gtbake
