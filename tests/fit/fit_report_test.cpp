// The fit report as code output (not the committed artifact): a report written from a fresh
// three-scene sweep shows every figure it links, beside it, leads with the band and the verdict,
// and renders in a real browser.
#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>
#include <string>

#include "common/atomic_file.h"
#include "common/output_set.h"
#include "fit/fit_command.h"
#include "synthetic_sweep.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

constexpr int kBounces = 3;

// A report from three cavity-law scenes (enough for the scene jackknife and its band).
const fs::path& report() {
  static const fs::path dir = [] {
    const fs::path sweep = test::freshDir("report_sweep");
    test::writeWalkSweep(
        sweep, {"bowl", "pit", "hole"}, 48, 48, 32, kBounces,
        [](double u) { return test::cavityLaw(u, kBounces); }, 9);
    FitOptions options;
    options.sweep = sweep;
    options.out = test::freshDir("report_fit") / "fit.json";
    options.progress = false;
    testing::internal::CaptureStdout();
    runFit(options);
    testing::internal::GetCapturedStdout();
    return options.out.parent_path() / "report";
  }();
  return dir;
}

TEST(Report, EveryImageItShowsIsBesideIt) {
  const std::string html = readFile(report() / "index.html");
  static const std::regex kImage("<img src='([^']+)'");
  std::size_t images = 0;
  for (std::sregex_iterator it(html.begin(), html.end(), kImage), end; it != end; ++it) {
    const std::string src = (*it)[1];
    EXPECT_EQ(src.find('/'), std::string::npos) << src << " is not a file beside the page";
    ASSERT_TRUE(fs::exists(report() / src)) << src;
    const std::string svg = readFile(report() / src);
    EXPECT_EQ(svg.rfind("<svg", 0), 0u) << src;
    EXPECT_NE(svg.find("</svg>"), std::string::npos) << src;
    // SVG is XML: HTML's named entities (&minus;, &rho;) break the image; only XML's five parse.
    static const std::regex kNamedEntity("&(?!(amp|lt|gt|quot|apos);)[A-Za-z]+;");
    EXPECT_FALSE(std::regex_search(svg, kNamedEntity)) << src;
    ++images;
  }
  // The band per albedo (7) and G(A) with the band (1), Figure 7 (4), Figure 6 per scene (3).
  EXPECT_EQ(images, 7u + 1u + 4u + 3u);
}

// The report is committed with the fit's output set when it lies inside it (the default,
// beside fit.json), every page and figure verified by the manifest; elsewhere it is a set of its
// own (fit_report.manifest.json).
TEST(Report, IsPartOfAnOutputSet) {
  const OutputManifest fit = readOutputSet(report().parent_path(), "fit");
  ASSERT_NE(fit.find("report/index.html"), nullptr);
  EXPECT_EQ(fit.readVerified("report/index.html"), readFile(report() / "index.html"));
  std::size_t svgs = 0;
  for (const OutputFile& f : fit.files)
    svgs += f.name.size() > 4 && f.name.rfind(".svg") == f.name.size() - 4;
  EXPECT_EQ(svgs, 7u + 1u + 4u + 3u);

  FitOptions options;
  options.sweep = report().parent_path().parent_path() / "report_sweep";
  options.out = test::freshDir("report_fit_elsewhere") / "fit.json";
  options.report = test::freshDir("report_elsewhere");
  options.progress = false;
  testing::internal::CaptureStdout();
  runFit(options);
  testing::internal::GetCapturedStdout();
  const OutputManifest own = readOutputSet(*options.report, "fit_report");
  EXPECT_EQ(own.readVerified("index.html"), readFile(*options.report / "index.html"));
  EXPECT_EQ(readOutputSet(options.out.parent_path(), "fit").find("report/index.html"), nullptr);
}

// The page leads with the band and the verdict on the shipped constants, before any table.
TEST(Report, LeadsWithTheBandAndTheVerdict) {
  const std::string html = readFile(report() / "index.html");
  const std::size_t band = html.find("How sure: the curve band");
  const std::size_t verdict = html.find("Shipped constants by range of A: ");
  const std::size_t first_table = html.find("<table>");
  ASSERT_NE(band, std::string::npos);
  ASSERT_NE(verdict, std::string::npos);
  EXPECT_LT(band, first_table);
  EXPECT_LT(verdict, first_table);
  EXPECT_NE(html.find("band_rho090.svg"), std::string::npos);
}

// Headless Chromium (Debian's chromium package) screenshots the page; a blank or failed render
// gives no or a tiny PNG. Skipped where Chromium is not installed.
TEST(Report, RendersInHeadlessChromium) {
  const fs::path chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) GTEST_SKIP() << "chromium is not installed (apt-get install chromium)";
  const fs::path dir = test::freshDir("report_render");
  const fs::path shot = dir / "report.png";
  const std::string command =
      chromium.string() +
      " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
      " --disable-background-networking --disable-component-update --disable-sync"
      " --user-data-dir=" +
      (dir / "profile").string() + " --window-size=1300,2400 --screenshot=" + shot.string() +
      " file://" + (report() / "index.html").string() + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  ASSERT_TRUE(fs::exists(shot));
  // A blank 1300x2400 page compresses to a few kB; the tables and figures take hundreds.
  EXPECT_GT(fs::file_size(shot), 100u * 1024u);
}

}  // namespace
}  // namespace gtbake
