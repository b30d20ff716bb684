#include "plot/svg_plot.h"

#include <cmath>

namespace gtbake {

namespace {

// A tick's value as printed: rounding residue of the tick positions (|v| < 1e-12, e.g. −2e−17)
// is zero, and a value that prints as zero carries no sign ("-0.0").
std::string tickLabel(double v, const char* format) {
  const std::string text = formatNumber(std::abs(v) < 1e-12 ? 0.0 : v, format);
  if (text[0] == '-' && text.find_first_not_of("0.", 1) == std::string::npos) return text.substr(1);
  return text;
}

}  // namespace

SvgPlot::SvgPlot(double x0, double x1, double y0, double y1, const std::string& title,
                 const std::string& xlabel, const std::string& ylabel)
    : x0_(x0), x1_(x1) {
  const double raw = (y1 - y0) / 5.0;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw <= decade       ? decade
                      : raw <= 2 * decade ? 2 * decade
                      : raw <= 5 * decade ? 5 * decade
                                          : 10 * decade;
  y0_ = std::floor(y0 / step + 1e-9) * step;
  y1_ = std::ceil(y1 / step - 1e-9) * step;
  const int y_ticks = static_cast<int>(std::lround((y1_ - y0_) / step));
  out_ << "<text x='" << kW / 2 << "' y='18' text-anchor='middle' font-size='14'>" << title
       << "</text>\n"
       << "<text x='" << (kL + kW - kR) / 2 << "' y='" << kH - 6 << "' text-anchor='middle'>"
       << xlabel << "</text>\n"
       << "<text transform='translate(14," << (kT + kH - kB) / 2
       << ") rotate(-90)' text-anchor='middle'>" << ylabel << "</text>\n";
  for (int t = 0; t <= 5; ++t) {
    const double x = x0 + (x1 - x0) * t / 5.0;
    out_ << "<line x1='" << px(x) << "' y1='" << py(y0_) << "' x2='" << px(x) << "' y2='" << py(y1_)
         << "' stroke='#ddd'/>\n<text x='" << px(x) << "' y='" << py(y0_) + 16
         << "' text-anchor='middle'>" << tickLabel(x, "%.1f") << "</text>\n";
  }
  for (int t = 0; t <= y_ticks; ++t) {
    const double y = y0_ + step * t;
    out_ << "<line x1='" << px(x0) << "' y1='" << py(y) << "' x2='" << px(x1) << "' y2='" << py(y)
         << "' stroke='#ddd'/>\n<text x='" << px(x0) - 4 << "' y='" << py(y) + 4
         << "' text-anchor='end'>" << tickLabel(y, "%g") << "</text>\n";
  }
  out_ << "<rect x='" << kL << "' y='" << kT << "' width='" << kW - kL - kR << "' height='"
       << kH - kT - kB << "' fill='none' stroke='black'/>\n";
}

void SvgPlot::legendBottomRight(int rows) {
  legend_origin_ = {kW - kR - 180, kH - kB - 8 - 16.0 * rows};
}

void SvgPlot::legendBelow(int rows) {
  below_ = 16.0 * rows + 4;
  legend_origin_ = {kL + 10, kH + 12};
}

void SvgPlot::points(const std::vector<double>& xs, const std::vector<double>& ys,
                     const char* color, double radius) {
  out_ << "<g fill='" << color << "' fill-opacity='0.45'>";
  for (std::size_t i = 0; i < xs.size(); ++i) {
    out_ << "<circle cx='" << formatNumber(px(xs[i]), "%.1f") << "' cy='"
         << formatNumber(py(ys[i]), "%.1f") << "' r='" << radius << "'/>";
  }
  out_ << "</g>\n";
}

void SvgPlot::curve(const std::vector<double>& xs, const std::vector<double>& ys, const char* color,
                    bool dashed, double width) {
  out_ << "<polyline fill='none' stroke='" << color << "' stroke-width='" << width << "'"
       << (dashed ? " stroke-dasharray='5,4'" : "") << " points='";
  for (std::size_t i = 0; i < xs.size(); ++i) {
    out_ << formatNumber(px(xs[i]), "%.1f") << ',' << formatNumber(py(ys[i]), "%.1f") << ' ';
  }
  out_ << "'/>\n";
}

void SvgPlot::band(const std::vector<double>& xs, const std::vector<double>& lo,
                   const std::vector<double>& hi, const char* color, double opacity) {
  out_ << "<polygon fill='" << color << "' fill-opacity='" << opacity << "' stroke='none' points='";
  for (std::size_t i = 0; i < xs.size(); ++i) {
    out_ << formatNumber(px(xs[i]), "%.1f") << ',' << formatNumber(py(hi[i]), "%.1f") << ' ';
  }
  for (std::size_t i = xs.size(); i-- > 0;) {
    out_ << formatNumber(px(xs[i]), "%.1f") << ',' << formatNumber(py(lo[i]), "%.1f") << ' ';
  }
  out_ << "'/>\n";
}

void SvgPlot::errorBar(double x, double y, double half, const char* color) {
  out_ << "<line x1='" << px(x) << "' y1='" << py(y - half) << "' x2='" << px(x) << "' y2='"
       << py(y + half) << "' stroke='" << color << "' stroke-width='1.5'/>"
       << "<circle cx='" << px(x) << "' cy='" << py(y) << "' r='3.5' fill='" << color << "'/>\n";
}

void SvgPlot::legend(const std::string& text, const char* color, bool dashed) {
  const double x = legend_origin_.first;
  const double y = legend_origin_.second + 16 * legend_rows_++;
  out_ << "<line x1='" << x << "' y1='" << y - 4 << "' x2='" << x + 24 << "' y2='" << y - 4
       << "' stroke='" << color << "' stroke-width='2'" << (dashed ? " stroke-dasharray='5,4'" : "")
       << "/><text x='" << x + 30 << "' y='" << y << "'>" << text << "</text>\n";
}

std::string SvgPlot::str() const {
  std::ostringstream svg;
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << kW << "' height='" << kH + below_
      << "' viewBox='0 0 " << kW << ' ' << kH + below_
      << "' font-family='sans-serif' font-size='12'>\n"
      << "<rect width='100%' height='100%' fill='white'/>\n"
      << out_.str() << "</svg>\n";
  return svg.str();
}

double SvgPlot::px(double x) const {
  return kL + (x - x0_) / (x1_ - x0_) * (kW - kL - kR);
}

double SvgPlot::py(double y) const {
  return kH - kB - (y - y0_) / (y1_ - y0_) * (kH - kT - kB);
}

}  // namespace gtbake
