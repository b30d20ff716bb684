// Output sets switch whole (docs/limits.md "Output sets"): a SIGKILL at every step of a commit, a
// full disk while the manifest is written, the user's files and nested directories beside a set,
// mount points and symlinked directories.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>

#include "common/error.h"
#include "common/output_set.h"
#include "reliability_util.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using test::gtbakeLeftovers;
using test::readBytes;
using test::ScopedEnv;
using test::spit;
using test::TempDir;

void writeSet(const fs::path& dir, const std::string& command, const std::string& tag) {
  OutputSet set(dir, command);
  set.add("a.txt", tag + " a");
  set.add("sub/b.bin", tag + " b");
  if (tag == "new") set.add("c.txt", "only in the new set");
  set.setSettings({{"tag", tag}});
  set.commit();
}

// A directory holding the old "demo" set, another command's set, and the user's own things.
void prepare(const fs::path& dir) {
  writeSet(dir, "demo", "old");
  {
    OutputSet other(dir, "other");
    other.add("other/o.txt", "another command's");
    other.commit();
  }
  spit(dir / "notes.txt", "mine");
  fs::create_directories(dir / "nested" / "deep");
  spit(dir / "nested" / "deep" / "user.txt", "deep");
  spit(dir / "sub" / "mine.txt", "beside the set's sub/b.bin");
  fs::create_symlink("notes.txt", dir / "link");
}

void expectUserFilesWhole(const fs::path& dir) {
  EXPECT_EQ(readBytes(dir / "notes.txt"), "mine");
  EXPECT_EQ(readBytes(dir / "nested" / "deep" / "user.txt"), "deep");
  EXPECT_EQ(readBytes(dir / "sub" / "mine.txt"), "beside the set's sub/b.bin");
  EXPECT_TRUE(fs::is_symlink(dir / "link"));
  EXPECT_EQ(fs::read_symlink(dir / "link"), "notes.txt");
  verifyOutputSet(readOutputSet(dir, "other"));
}

// "old" or "new": which complete set the directory holds (throws unless one verifies).
std::string setIn(const fs::path& dir) {
  const OutputManifest m = readOutputSet(dir, "demo");
  verifyOutputSet(m);
  const std::string tag = m.settings.at("tag").get<std::string>();
  EXPECT_EQ(readBytes(dir / "a.txt"), tag + " a");
  EXPECT_EQ(fs::exists(dir / "c.txt"), tag == "new");
  return tag;
}

TEST(OutputSet, SigkillAtEveryStepOfACommitLeavesTheOldOrTheNewSet) {
  const std::pair<const char*, const char*> points[] = {
      {"commit-start", "old"},  {"commit-linked", "old"},    {"commit-manifest", "old"},
      {"commit-synced", "old"}, {"commit-exchanged", "new"}, {"commit-done", "new"}};
  for (const auto& [point, expected] : points) {
    TempDir root("kill");
    const fs::path dir = root.path() / "out";
    prepare(dir);
    const pid_t child = ::fork();
    if (child == 0) {
      ::setenv("GTBAKE_TEST_KILL_AT", point, 1);
      try {
        writeSet(dir, "demo", "new");
      } catch (...) {
      }
      std::_Exit(3);  // not killed: the hook did not fire
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << point;
    EXPECT_EQ(setIn(dir), expected) << point;
    expectUserFilesWhole(dir);
    // The next writer removes what the killed one left (its stage, the old tree) and nothing else.
    writeSet(dir, "demo", "old");
    EXPECT_EQ(setIn(dir), "old") << point;
    expectUserFilesWhole(dir);
    EXPECT_EQ(gtbakeLeftovers(dir), std::vector<std::string>{}) << point;
  }
}

TEST(OutputSet, FullDiskWhileWritingTheManifestKeepsTheOldSet) {
  TempDir root("manifest_enospc");
  const fs::path dir = root.path() / "out";
  prepare(dir);
  {
    const ScopedEnv fail("GTBAKE_TEST_FAIL_WRITE", "demo.manifest.json");
    try {
      writeSet(dir, "demo", "new");
      FAIL() << "the injected failure was not reported";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("No space left"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(setIn(dir), "old");
  expectUserFilesWhole(dir);
  EXPECT_EQ(gtbakeLeftovers(dir), std::vector<std::string>{});
}

TEST(OutputSet, CommitKeepsUserFilesNestedSetsAndDropsOnlyItsOwnOldFiles) {
  TempDir root("keep");
  const fs::path dir = root.path() / "out";
  prepare(dir);
  writeSet(dir / "nested", "inner", "inner");
  struct stat before {};
  ASSERT_EQ(::stat((dir / "notes.txt").c_str(), &before), 0);
  fs::permissions(dir, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec);
  {
    OutputSet set(dir, "demo");
    set.add("a.txt", "new a");
    set.setSettings({{"tag", "new"}});
    set.commit();
  }
  EXPECT_FALSE(fs::exists(dir / "sub" / "b.bin"));  // the old set's, not in the new one
  EXPECT_FALSE(fs::exists(dir / "c.txt"));
  EXPECT_EQ(readBytes(dir / "a.txt"), "new a");
  expectUserFilesWhole(dir);
  verifyOutputSet(readOutputSet(dir / "nested", "inner"));
  struct stat after {};
  ASSERT_EQ(::stat((dir / "notes.txt").c_str(), &after), 0);
  EXPECT_EQ(before.st_ino, after.st_ino);  // the user's file itself, linked, not a copy
  EXPECT_EQ(fs::status(dir).permissions(),
            fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec);
  EXPECT_EQ(gtbakeLeftovers(dir), std::vector<std::string>{});
}

TEST(OutputSet, AUserFileWhereTheSetNeedsADirectoryIsAnError) {
  TempDir root("in_the_way");
  const fs::path dir = root.path() / "out";
  fs::create_directories(dir);
  spit(dir / "report", "the user's file named report");
  fs::create_directories(dir / "fit.json");
  OutputSet set(dir, "demo");
  EXPECT_THROW(set.add("report/index.html", "x"), Error);
  EXPECT_THROW(set.add("fit.json", "{}"), Error);
  EXPECT_EQ(readBytes(dir / "report"), "the user's file named report");
}

TEST(OutputSet, SymlinkedDirectoryIsWrittenThroughAndStaysALink) {
  TempDir root("symlinked");
  fs::create_directories(root.path() / "real");
  fs::create_directory_symlink("real", root.path() / "out");
  writeSet(root.path() / "out", "demo", "new");
  EXPECT_TRUE(fs::is_symlink(root.path() / "out"));
  EXPECT_EQ(setIn(root.path() / "real"), "new");
  EXPECT_EQ(gtbakeLeftovers(root.path() / "real"), std::vector<std::string>{});
}

// `--out .`: the process's working directory is the one switched; it follows the switch, so
// relative paths written afterwards land in the new directory, not in the removed old tree.
TEST(OutputSet, AWorkingDirectoryInsideFollowsTheSwitch) {
  TempDir root("cwd");
  const fs::path dir = root.path() / "out";
  fs::create_directories(dir / "sub");
  const fs::path before = fs::current_path();
  fs::current_path(dir / "sub");
  writeSet("..", "demo", "new");
  spit("after.txt", "written after the switch");
  fs::current_path(before);
  EXPECT_EQ(readBytes(dir / "sub" / "after.txt"), "written after the switch");
  EXPECT_EQ(setIn(dir), "new");
}

TEST(OutputSet, AMountPointIsRefusedBeforeAnythingIsWritten) {
  TempDir root("mountpoint");
  const fs::path mount = root.path() / "mnt";
  fs::create_directories(mount);
  const std::string cmd = "mount -t tmpfs -o size=1m tmpfs " + mount.string() + " 2>/dev/null";
  if (std::system(cmd.c_str()) != 0) GTEST_SKIP() << "cannot mount a tmpfs here";
  struct Unmount {
    fs::path p;
    ~Unmount() { (void)!std::system(("umount " + p.string()).c_str()); }
  } unmount{mount};
  try {
    OutputSet set(mount, "demo");
    FAIL() << "a mount point was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a mount point"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(mount));
  EXPECT_EQ(gtbakeLeftovers(mount), std::vector<std::string>{});
  writeSet(mount / "inside", "demo", "new");  // a directory inside it switches as usual
  EXPECT_EQ(setIn(mount / "inside"), "new");
}

}  // namespace
}  // namespace gtbake
