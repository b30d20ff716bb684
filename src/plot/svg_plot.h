// A minimal SVG line / scatter / band plot in data coordinates, for the fit report (no
// dependencies, crisp at any zoom). The y axis is widened to a 1-2-5 step so tick labels are
// round numbers.
#pragma once

#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/text_format.h"

namespace gtbake {

class SvgPlot {
 public:
  SvgPlot(double x0, double x1, double y0, double y1, const std::string& title,
          const std::string& xlabel, const std::string& ylabel);

  // Legends go top-left by default, bottom-right for plots whose curves fill the top-left, or
  // below the axes (the picture grows by `rows` lines) where curves may pass anywhere.
  void legendBottomRight(int rows);
  void legendBelow(int rows);
  void points(const std::vector<double>& xs, const std::vector<double>& ys, const char* color,
              double radius = 1.5);
  void curve(const std::vector<double>& xs, const std::vector<double>& ys, const char* color,
             bool dashed = false, double width = 1.6);
  // A filled region between lo(x) and hi(x).
  void band(const std::vector<double>& xs, const std::vector<double>& lo,
            const std::vector<double>& hi, const char* color, double opacity = 0.25);
  void errorBar(double x, double y, double half, const char* color);
  void legend(const std::string& text, const char* color, bool dashed = false);
  std::string str() const;

 private:
  static constexpr double kW = 440, kH = 340, kL = 56, kR = 14, kT = 28, kB = 40;
  double px(double x) const;
  double py(double y) const;

  double x0_, x1_, y0_ = 0.0, y1_ = 1.0;
  int legend_rows_ = 0;
  double below_ = 0.0;  // height added under the picture for a legend below the axes
  std::pair<double, double> legend_origin_{kL + 10, kT + 14};
  std::ostringstream out_;
};

}  // namespace gtbake
