// The report plots' axes (fit/svg_plot.h): tick labels as a reader expects them, and a legend
// below the axes that no curve can cross.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

#include "plot/svg_plot.h"

namespace gtbake {
namespace {

// tune's thickness axis, log10 of [0.125, 4] m: its fourth x tick is −1.1e−16 in floating point.
TEST(SvgPlot, TickAtRoundingResidueReadsZeroWithoutSign) {
  const double x0 = std::log10(0.125);
  const double x1 = std::log10(4.0);
  ASSERT_LT(x0 + (x1 - x0) * 3 / 5.0, 0.0);  // the residue this test is about
  const std::string svg = SvgPlot(x0, x1, -0.2, 0.2, "t", "x", "y").str();
  EXPECT_EQ(svg.find(">-0.0<"), std::string::npos) << svg;
  EXPECT_EQ(svg.find(">-0<"), std::string::npos) << svg;
  EXPECT_NE(svg.find(">0.0<"), std::string::npos);
  EXPECT_NE(svg.find(">0<"), std::string::npos);     // the y tick at 0
  EXPECT_NE(svg.find(">-0.3<"), std::string::npos);  // real negatives keep their sign
  EXPECT_NE(svg.find(">-0.2<"), std::string::npos);
  // A tick that is not zero but prints as one (−0.04 at one decimal) reads 0.0 too.
  const std::string small = SvgPlot(-0.04, 0.96, 0.0, 1.0, "t", "x", "y").str();
  EXPECT_EQ(small.find(">-0.0<"), std::string::npos) << small;
  EXPECT_NE(small.find(">0.0<"), std::string::npos);
}

int svgHeight(const std::string& svg) {
  std::smatch m;
  EXPECT_TRUE(std::regex_search(svg, m, std::regex("<svg [^>]*height='([0-9.]+)'")));
  return std::stoi(m[1]);
}

// A legend below the axes grows the picture by its rows and starts under the plot area; the
// default legend leaves the size alone.
TEST(SvgPlot, LegendBelowGrowsThePictureUnderTheAxes) {
  SvgPlot inside(0, 1, 0, 1, "t", "x", "y");
  inside.legend("a", "#000");
  SvgPlot below(0, 1, 0, 1, "t", "x", "y");
  below.legendBelow(3);
  for (const char* text : {"a", "b", "c"}) below.legend(text, "#000");
  const int h0 = svgHeight(inside.str());
  EXPECT_EQ(svgHeight(below.str()), h0 + 3 * 16 + 4);
  std::smatch m;
  const std::string svg = below.str();
  ASSERT_TRUE(std::regex_search(svg, m, std::regex("<text x='[0-9.]+' y='([0-9.]+)'>a</text>")));
  EXPECT_GT(std::stod(m[1]), h0);  // below the x axis label's line, inside the picture
  EXPECT_LT(std::stod(m[1]) + 2 * 16, h0 + 3 * 16 + 4);
}

}  // namespace
}  // namespace gtbake
