#include "fit/validate_report.h"

#include <cmath>

#include "common/text_format.h"

namespace gtbake {

namespace {

// The bins of a range of A: [lo · bins, hi · bins).
std::size_t binIndex(double edge) {
  return static_cast<std::size_t>(std::lround(edge * kValidateBins));
}

// Σ over views (those with include[v], all when empty) and albedos of the squared difference
// between `given` and each view's refit, over bins [first, last), and the points counted.
struct SquaredSum {
  double sum = 0.0;
  double points = 0.0;
};
SquaredSum squaredDifference(const ValidateData& d, const MultiBounceCoeffs& given,
                             const std::vector<MultiBounceCoeffs>& refit_of_view, std::size_t first,
                             std::size_t last, const std::vector<char>& include) {
  SquaredSum out;
  for (std::size_t v = 0; v < d.views.size(); ++v) {
    if (!include.empty() && include[v] == 0) continue;
    out.points += pointCount(d.views[v], first, last);
    for (double rho : d.albedos) {
      out.sum += sumSquaredDifference(d.views[v], first, last, cubicAt(given, rho),
                                      cubicAt(refit_of_view[v], rho));
    }
  }
  return out;
}

double rms(const SquaredSum& s, std::size_t albedos) {
  return s.points > 0.0 ? std::sqrt(s.sum / (s.points * static_cast<double>(albedos))) : 0.0;
}

PixelDifference pixelDifference(const ValidateData& d, const MultiBounceCoeffs& given) {
  PixelDifference out;
  const std::vector<MultiBounceCoeffs> refit(d.views.size(), d.refit);
  out.rms = rms(squaredDifference(d, given, refit, 0, kValidateBins, {}), d.albedos.size());
  const SceneJackknife& jk = d.scene_jackknife;
  if (!jk.available) return out;
  const std::vector<std::size_t> scene = groupViews(d.views, &ViewSums::scene).of;
  std::vector<double> replicas;
  for (std::size_t s = 0; s < jk.leave_one_out.size(); ++s) {
    std::vector<char> include(d.views.size());
    for (std::size_t v = 0; v < include.size(); ++v) include[v] = scene[v] != s ? 1 : 0;
    const std::vector<MultiBounceCoeffs> without(d.views.size(), jk.leave_one_out[s].linear);
    replicas.push_back(
        rms(squaredDifference(d, given, without, 0, kValidateBins, include), d.albedos.size()));
  }
  out.se = jackknifeSe(replicas);
  const double t = studentT975(replicas.size() - 1);
  out.lo = std::max(0.0, out.rms - t * out.se);
  out.hi = out.rms + t * out.se;
  out.interval = true;
  return out;
}

void fillRangePixels(const ValidateData& d, const MultiBounceCoeffs& given, CurveVerdict& v) {
  const std::vector<MultiBounceCoeffs> refit(d.views.size(), d.refit);
  const double total = static_cast<double>(d.points());
  for (RangeScore& r : v.ranges) {
    const SquaredSum s = squaredDifference(d, given, refit, binIndex(r.lo), binIndex(r.hi), {});
    r.pixel_share = total > 0.0 ? s.points / total : 0.0;
    r.pixel_rms_difference = rms(s, d.albedos.size());
  }
}

// Squared errors of G per view and albedo for per-view constants: [view][albedo].
std::vector<std::vector<double>> squaredErrors(const ValidateData& d,
                                               const std::vector<MultiBounceCoeffs>& of_view) {
  std::vector<std::vector<double>> out(d.views.size());
  for (std::size_t v = 0; v < d.views.size(); ++v) {
    for (std::size_t j = 0; j < d.albedos.size(); ++j) {
      out[v].push_back(
          sumSquaredError(d.views[v], 0, kValidateBins, j, cubicAt(of_view[v], d.albedos[j])));
    }
  }
  return out;
}

// The RMSE tables of the three sets of constants.
void fillErrors(const ValidateData& d, const MultiBounceCoeffs& given, ValidateReport& r) {
  const std::size_t V = d.views.size(), J = d.albedos.size();
  const SceneJackknife& jk = d.scene_jackknife;
  std::vector<MultiBounceCoeffs> held(V, d.refit);
  if (jk.available) {
    const std::vector<std::size_t> scene = groupViews(d.views, &ViewSums::scene).of;
    for (std::size_t v = 0; v < V; ++v) held[v] = jk.leave_one_out[scene[v]].linear;
  }
  const std::vector<std::vector<double>> e[3] = {squaredErrors(d, std::vector(V, given)),
                                                 squaredErrors(d, std::vector(V, d.refit)),
                                                 squaredErrors(d, held)};
  const auto row = [&](std::string label, double points, auto&& sum) {
    RmseRow out{std::move(label)};
    out.points = points;
    double* fields[3] = {&out.given, &out.refit, &out.held_out};
    for (int k = 0; k < (jk.available ? 3 : 2); ++k) {
      *fields[k] = points > 0.0 ? std::sqrt(sum(e[k]) / points) : 0.0;
    }
    return out;
  };
  const double N = static_cast<double>(d.points());
  for (std::size_t j = 0; j < J; ++j) {
    r.per_albedo.push_back(row(formatNumber(d.albedos[j], "%.2f"), N, [&](const auto& s) {
      double sum = 0.0;
      for (std::size_t v = 0; v < V; ++v) sum += s[v][j];
      return sum;
    }));
    r.per_albedo.back().floor = d.floor_per_albedo[j];
  }
  for (std::size_t v = 0; v < V; ++v) {
    const double n = pointCount(d.views[v], 0, kValidateBins) * static_cast<double>(J);
    r.per_view.push_back(row(d.views[v].name, n, [&](const auto& s) {
      double sum = 0.0;
      for (double x : s[v]) sum += x;
      return sum;
    }));
    r.per_view.back().points = n / static_cast<double>(J);
    r.per_view.back().floor = d.views[v].floor_rmse;
    r.per_view.back().weight_share = d.views[v].weight_share;
  }
  r.all = row("all", N * static_cast<double>(J), [&](const auto& s) {
    double sum = 0.0;
    for (const std::vector<double>& view : s) {
      for (double x : view) sum += x;
    }
    return sum;
  });
  r.all.points = N;
  r.all.floor = d.floor_rmse;
}

}  // namespace

ValidateReport validateReport(const ValidateData& d, const MultiBounceCoeffs& given,
                              const VerdictRule& rule) {
  ValidateReport r;
  r.given = given;
  r.verdict = judgeCurve(d.scene_jackknife, d.refit, given, rule);
  fillRangePixels(d, given, r.verdict);
  r.rms_difference = pixelDifference(d, given);
  r.max_difference = maxCurveDifference(d.refit, given);
  for (int i = 0; i < 6; ++i) {
    r.coefficients.push_back({kCoeffNames[i], given[i], d.refit[i],
                              d.scene_jackknife.available ? d.scene_jackknife.se[i] : 0.0,
                              d.mc_se[i]});
  }
  fillErrors(d, given, r);
  return r;
}

}  // namespace gtbake
