// Output sets, the checked writer, SHA-256 and the stale-temporary cleanup (src/common).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_lock.h"
#include "common/output_set.h"
#include "common/sha256.h"
#include "reliability_util.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using test::gtbakeLeftovers;
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

// The errors name the command line to rerun, not the set's file name.
TEST(OutputSet, ErrorsNameTheCommandToRerun) {
  TempDir dir("rerun_names");
  for (const auto& [set, command] :
       {std::pair<const char*, const char*>{"validate_gtso", "`gtbake validate-gtso`"},
        {"screen_ao", "`gtbake screen-ao`"},
        {"shard", "`gtbake sweep --shard`"},
        {"fit", "`gtbake fit`"}}) {
    try {
      readOutputSet(dir.path(), set);
      ADD_FAILURE() << set;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(command), std::string::npos) << e.what();
    }
  }
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
  EXPECT_EQ(gtbakeLeftovers(dir.path()), std::vector<std::string>{});
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
  EXPECT_FALSE(fs::exists(mount / ("keep.bin.gtbake-tmp-" + std::to_string(::getpid()))));
}

TEST(CheckedWriter, InjectedFailureNeverReplacesTheOldFile) {
  TempDir dir("inject");
  writeFileAtomically(dir.path() / "f.json", "old");
  const ScopedEnv fail("GTBAKE_TEST_FAIL_WRITE", "f.json");
  EXPECT_THROW(writeFileAtomically(dir.path() / "f.json", "new contents"), Error);
  EXPECT_EQ(readBytes(dir.path() / "f.json"), "old");
}

// A child killed by SIGTERM while its set is staged leaves nothing behind: no stage, no lock.
TEST(Signals, TermRemovesTheStageAndTheLock) {
  TempDir root("signal");
  const fs::path dir = root.path() / "out";
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  if (child == 0) {
    OutputSet set(dir, "demo");
    set.add("a.bin", "staged");
    set.add("sub/b.bin", "staged too");
    const char byte = 1;
    (void)!::write(ready[1], &byte, 1);
    ::pause();
    std::_Exit(0);
  }
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  EXPECT_EQ(gtbakeLeftovers(dir).size(), 2u);  // the stage and the lock file
  ::kill(child, SIGTERM);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  EXPECT_EQ(gtbakeLeftovers(dir), std::vector<std::string>{});
  EXPECT_TRUE(fs::is_empty(dir));
  ::close(ready[0]);
  ::close(ready[1]);
}

// A pid that no longer runs.
pid_t deadPid() {
  const pid_t child = ::fork();
  if (child == 0) std::_Exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

// SIGKILL cannot be caught: the next run removes what the killed one left, and only that.
TEST(Signals, StaleTemporariesOfADeadProcessAreCleanedNextRun) {
  TempDir dir("stale");
  const std::string dead = std::to_string(deadPid());
  const fs::path stale = dir.path() / ("sweep.json.gtbake-tmp-" + dead);
  spit(stale, "half");
  const fs::path live = dir.path() / ("x.gtbake-tmp-" + std::to_string(::getppid()));
  spit(live, "parent's");
  // The user's own names, even when they look like temporaries of a dead process.
  const std::vector<fs::path> users = {dir.path() / "thesis.tmp-4242",
                                       dir.path() / ("thesis.tmp-" + dead),
                                       dir.path() / "notes.gtbake-tmp-draft"};
  for (const fs::path& p : users) spit(p, "the user's");
  fs::create_directories(dir.path() / ("folder.gtbake-tmp-" + dead));
  const auto removed = cleanStaleTemporaries(dir.path());
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  for (const fs::path& p : users) EXPECT_EQ(readBytes(p), "the user's") << p;
  EXPECT_TRUE(fs::is_directory(dir.path() / ("folder.gtbake-tmp-" + dead)));
}

// A stage left by a SIGKILLed writer is removed by the next writer; a directory of the same
// name without our marker (the user's) is not.
TEST(Signals, OnlyMarkedStagesOfDeadProcessesAreRemoved) {
  TempDir root("stale_stage");
  const fs::path dir = root.path() / "out";
  const pid_t child = ::fork();
  if (child == 0) {
    OutputSet* set = new OutputSet(dir, "demo");  // never destroyed: as if killed
    set->add("a.txt", "staged");
    std::_Exit(0);
  }
  ::waitpid(child, nullptr, 0);
  ASSERT_EQ(gtbakeLeftovers(dir).size(), 2u);
  const fs::path user = root.path() / (".out.gtbake-stage-" + std::to_string(deadPid()) + "-0");
  fs::create_directories(user);
  spit(user / "keep.txt", "the user's");
  {
    OutputSet set(dir, "demo");
    set.add("a.txt", "new");
    set.commit();
  }
  EXPECT_EQ(gtbakeLeftovers(dir), std::vector<std::string>{user.string()});
  EXPECT_EQ(readBytes(user / "keep.txt"), "the user's");
}

// A marked stage whose pid is running again, but as a process started at another time (a reused
// pid), is stale; the marker's start time tells them apart.
TEST(Signals, AStageOfAReusedPidIsStale) {
  TempDir root("reused_pid");
  const fs::path dir = root.path() / "out";
  const std::string live = std::to_string(::getppid());
  const fs::path stage = root.path() / (".out.gtbake-stage-" + live + "-0");
  fs::create_directories(stage / "tree");
  spit(stage / "gtbake-stage.json",
       R"({"tool":"gtbake","pid":)" + live + R"(,"start":"1","dir":")" + dir.string() + "\"}");
  {
    OutputSet set(dir, "demo");
    set.add("a.txt", "a");
    set.commit();
  }
  EXPECT_FALSE(fs::exists(stage));
}

// Two writers of one directory: the second is refused at once, naming the directory and the pid
// of the first, and writes nothing; a writer inside it is refused too; the first one succeeds.
TEST(OutputSet, ASecondWriterGetsTheLockErrorAndTheFirstSucceeds) {
  TempDir root("two_writers");
  const fs::path dir = root.path() / "out";
  int ready[2], go[2];
  ASSERT_EQ(::pipe(ready), 0);
  ASSERT_EQ(::pipe(go), 0);
  const pid_t first = ::fork();
  if (first == 0) {
    int code = 1;
    try {
      OutputSet set(dir, "demo");
      set.add("a.txt", "first");
      const char byte = 1;
      (void)!::write(ready[1], &byte, 1);
      char wait = 0;
      (void)!::read(go[0], &wait, 1);
      set.commit();
      code = 0;
    } catch (...) {
    }
    std::_Exit(code);
  }
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  const std::string pid = "(pid " + std::to_string(first) + ")";
  for (const fs::path& target : {dir, dir / "inner"}) {
    try {
      OutputSet set(target, "demo");
      ADD_FAILURE() << "a second writer of " << target << " was let in";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(dir.string() + " is being written by another gtbake"), std::string::npos)
          << what;
      EXPECT_NE(what.find(pid), std::string::npos) << what;
    }
  }
  EXPECT_FALSE(fs::exists(dir / "inner"));
  (void)!::write(go[1], &byte, 1);
  int status = 0;
  ::waitpid(first, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_EQ(readOutputSet(dir, "demo").readVerified("a.txt"), "first");
  EXPECT_EQ(gtbakeLeftovers(dir), std::vector<std::string>{});
  for (int fd : {ready[0], ready[1], go[0], go[1]}) ::close(fd);
}

// A writer of a directory that holds a busy one waits, at its commit, for the inner writer to
// finish, and its new tree carries the inner writer's new set (no update is lost).
TEST(OutputSet, ACommitWaitsForAWriterInsideItsDirectory) {
  TempDir root("nested_writer");
  const fs::path dir = root.path() / "out";
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t inner = ::fork();
  if (inner == 0) {
    OutputSet set(dir / "inner", "inner");
    set.add("i.txt", "inner's");
    const char byte = 1;
    (void)!::write(ready[1], &byte, 1);
    ::usleep(300000);
    set.commit();
    std::_Exit(0);
  }
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  {
    OutputSet set(dir, "outer");
    set.add("o.txt", "outer's");
    set.commit();  // blocks until the inner writer is done
  }
  ::waitpid(inner, nullptr, 0);
  EXPECT_EQ(readOutputSet(dir / "inner", "inner").readVerified("i.txt"), "inner's");
  EXPECT_EQ(readOutputSet(dir, "outer").readVerified("o.txt"), "outer's");
  EXPECT_EQ(gtbakeLeftovers(dir), std::vector<std::string>{});
  ::close(ready[0]);
  ::close(ready[1]);
}

// One process may lock a directory more than once (gtbake all and its stages).
TEST(OutputSet, LocksAreReentrantWithinAProcess) {
  TempDir root("reentrant");
  const fs::path dir = root.path() / "out";
  const OutputLock whole_run(dir);
  OutputSet set(dir, "demo");
  set.add("a.txt", "a");
  set.commit();
  OutputSet inner(dir / "gtso", "gtso");
  inner.add("g.txt", "g");
  inner.commit();
  verifyOutputSet(readOutputSet(dir, "demo"));
}

// A FIFO, socket or device node named as an output is refused, never replaced or opened.
TEST(OutputPaths, SpecialFilesAreRefusedAsOutputs) {
  TempDir dir("special");
  std::vector<fs::path> specials = {dir.path() / "fifo", dir.path() / "socket"};
  ASSERT_EQ(::mkfifo(specials[0].c_str(), 0644), 0);
  const int sock = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::snprintf(address.sun_path, sizeof(address.sun_path), "%s", specials[1].c_str());
  ASSERT_EQ(::bind(sock, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
  if (::mknod((dir.path() / "null").c_str(), S_IFCHR | 0666, ::makedev(1, 3)) == 0) {
    specials.push_back(dir.path() / "null");
  }
  for (const fs::path& p : specials) {
    const fs::file_type type = fs::status(p).type();
    EXPECT_THROW(OutputSet(p, "demo"), Error) << p;
    EXPECT_THROW(checkOutputFile(p, "--out", {}), Error) << p;
    EXPECT_THROW(writeFileAtomically(p, "x"), Error) << p;
    EXPECT_THROW(ensureDirectory(p), Error) << p;
    EXPECT_EQ(fs::status(p).type(), type) << p;
  }
  ::close(sock);
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
