// The fit report is a page a person opens: self-contained, and it renders in a real browser.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>

#include "cli_harness.h"

namespace gtbake::test {
namespace {

namespace fs = std::filesystem;

const fs::path kReport = fs::path(GTBAKE_SOURCE_DIR) / "luts" / "report";

TEST(Report, EveryImageItShowsIsBesideIt) {
  const std::string html = readBytes(kReport / "index.html");
  ASSERT_FALSE(html.empty());
  static const std::regex kImage("<img src='([^']+)'");
  size_t images = 0;
  for (std::sregex_iterator it(html.begin(), html.end(), kImage), end; it != end; ++it) {
    const std::string src = (*it)[1];
    EXPECT_EQ(src.find('/'), std::string::npos) << src << " is not a file beside the page";
    EXPECT_TRUE(fs::exists(kReport / src)) << src;
    ++images;
  }
  EXPECT_GE(images, 11u);  // Figure 6 per scene (7), Figure 7 (4), the refit vs shipped curves
}

// Headless Chromium (Debian's chromium package) screenshots the page; a blank or failed render
// gives no or a tiny PNG. Skipped where Chromium is not installed.
TEST(Report, RendersInHeadlessChromium) {
  const fs::path chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) GTEST_SKIP() << "chromium is not installed (apt-get install chromium)";
  const TempDir dir("report");
  const fs::path shot = dir.path() / "report.png";
  const std::string command =
      chromium.string() +
      " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
      " --disable-background-networking --disable-component-update --disable-sync"
      " --user-data-dir=" +
      (dir.path() / "profile").string() + " --window-size=1300,2400 --screenshot=" + shot.string() +
      " file://" + (kReport / "index.html").string() + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  ASSERT_TRUE(fs::exists(shot));
  // A blank 1300x2400 page compresses to a few kB; the tables and figures take hundreds.
  EXPECT_GT(fs::file_size(shot), 100u * 1024u);
}

}  // namespace
}  // namespace gtbake::test
