#include "screen_ao/screen_ao_stats.h"

#include <algorithm>
#include <cmath>

#include "common/math_constants.h"
#include "sweep/sweep_set.h"

namespace gtbake {

namespace {

struct Samples {
  std::vector<double> error;
  std::vector<double> error_at_radius;
  std::vector<double> angle;
};

ErrorSummary summarise(const Samples& s, double lo, double hi) {
  ErrorSummary e;
  e.lo = lo;
  e.hi = hi;
  e.pixels = s.error.size();
  auto moments = [](const std::vector<double>& v, double* bias, double* rmse) {
    double sum = 0.0;
    double sq = 0.0;
    for (double x : v) {
      sum += x;
      sq += x * x;
    }
    *bias = v.empty() ? 0.0 : sum / v.size();
    *rmse = v.empty() ? 0.0 : std::sqrt(sq / v.size());
  };
  moments(s.error, &e.bias, &e.rmse);
  e.pixels_at_radius = s.error_at_radius.size();
  moments(s.error_at_radius, &e.bias_at_radius, &e.rmse_at_radius);
  if (!s.angle.empty()) {
    double sum = 0.0;
    for (double a : s.angle) sum += a;
    e.bent_mean_deg = sum / s.angle.size();
    std::vector<double> sorted = s.angle;
    const std::size_t rank =
        static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(sorted.size()))) - 1;
    std::nth_element(sorted.begin(), sorted.begin() + rank, sorted.end());
    e.bent_p95_deg = sorted[rank];
  }
  return e;
}

void append(Samples* to, const Samples& from) {
  to->error.insert(to->error.end(), from.error.begin(), from.error.end());
  to->error_at_radius.insert(to->error_at_radius.end(), from.error_at_radius.begin(),
                             from.error_at_radius.end());
  to->angle.insert(to->angle.end(), from.angle.begin(), from.angle.end());
}

GroupErrors summariseGroup(const std::string& name, const std::vector<Samples>& bins) {
  GroupErrors g;
  g.group = name;
  Samples all;
  for (int b = 0; b < kErrorBins; ++b) {
    g.bins.push_back(summarise(bins[b], b / 10.0, (b + 1) / 10.0));
    append(&all, bins[b]);
  }
  g.all = summarise(all, 0.0, 1.0);
  return g;
}

}  // namespace

double angleDegrees(const float* a, const float* b) {
  const double d = static_cast<double>(a[0]) * b[0] + static_cast<double>(a[1]) * b[1] +
                   static_cast<double>(a[2]) * b[2];
  return std::acos(std::clamp(d, -1.0, 1.0)) * 180.0 / kPi;
}

std::vector<GroupErrors> errorStatistics(const std::vector<SweepImage>& images,
                                         const std::vector<AoEstimate>& estimates, double radius) {
  std::vector<std::string> order;
  std::vector<std::vector<Samples>> groups;
  for (std::size_t k = 0; k < images.size(); ++k) {
    const SweepImage& image = images[k];
    auto found = std::find(order.begin(), order.end(), image.group);
    if (found == order.end()) {
      order.push_back(image.group);
      groups.emplace_back(kErrorBins);
      found = order.end() - 1;
    }
    std::vector<Samples>& bins = groups[found - order.begin()];
    const auto at_radius = image.truth.a_at_radius.find(gbufferRadiusChannelName(radius));
    const std::vector<float>* a_r =
        at_radius == image.truth.a_at_radius.end() ? nullptr : &at_radius->second;
    for (std::size_t p = 0; p < image.gbuffer.pixels(); ++p) {
      if (image.gbuffer.mask[p] == 0) continue;
      const double a = image.truth.a[p];
      Samples& s = bins[std::clamp(static_cast<int>(std::floor(a * 10.0)), 0, kErrorBins - 1)];
      s.error.push_back(estimates[k].a[p] - a);
      if (a_r != nullptr) s.error_at_radius.push_back(estimates[k].a[p] - (*a_r)[p]);
      s.angle.push_back(angleDegrees(&estimates[k].bent[3 * p], &image.truth.bent[3 * p]));
    }
  }
  std::vector<GroupErrors> result;
  std::vector<Samples> everything(kErrorBins);
  for (std::size_t g = 0; g < order.size(); ++g) {
    result.push_back(summariseGroup(order[g], groups[g]));
    for (int b = 0; b < kErrorBins; ++b) append(&everything[b], groups[g][b]);
  }
  result.push_back(summariseGroup("all", everything));
  return result;
}

}  // namespace gtbake
