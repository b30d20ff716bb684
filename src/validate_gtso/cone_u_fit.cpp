#include "validate_gtso/cone_u_fit.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "common/error.h"
#include "gtso/cone_intersection.h"

namespace gtbake {

namespace {

constexpr std::size_t kChunk = 4096;    // samples per reduction chunk: fixed, so the sum's order
                                        // (and its bits) does not depend on the thread count
constexpr int kGridSteps = 12;          // coarse scan of log10 u before the minimiser
constexpr int kBisections = 12;         // profile-interval bisections per side: 12/2^12 decades
constexpr double kGoldenWidth = 0.02;   // decades: the golden-section bracket's final width
constexpr double kRefineFinest = 1e-5;  // decades: the last parabola's half-width
// Relative distance of the model's RMSE from the bisection's bound below which a step is decided
// by an exact SSE. Towards u = 1, where the SSE turns steeply, the model (the cone SSE table,
// cubic between grid values) can be off by more: the end check then reruns that side exactly.
constexpr double kModelMargin = 1e-2;

// Per-roughness SSE of S_cone(u) over every sample with r_p > 0, memoised by u: both subsets
// (all r_p, r_p ≥ 0.3) of one convention share the grid and the fixed-u evaluations.
class Objective {
 public:
  struct Entry {
    double sse = 0.0;
    std::size_t count = 0;
    bool done = false;
  };

  Objective(const std::vector<SpecularSample>& samples, bool perceptual) : perceptual_(perceptual) {
    std::size_t n = 0;
    for (const SpecularSample& x : samples) {
      if (static_cast<std::size_t>(x.roughness) >= roughness_.size()) {
        roughness_.resize(x.roughness + 1, 0.0f);
      }
      roughness_[x.roughness] = x.r_p;
      if (x.r_p > 0.0f) ++n;
    }
    // The samples with r_p > 0 in sample order, cut into chunks of kChunk; within a chunk grouped
    // by roughness, each group keeping sample order. A chunk's sum for one roughness then adds
    // the same terms in the same order as a pass over the whole chunk that skips the other
    // roughness values, and a pass can skip the roughness values it does not need.
    const std::size_t R = roughness_.size();
    chunks_ = (n + kChunk - 1) / kChunk;
    begin_.assign(chunks_ * R + 1, 0);
    std::size_t k = 0;
    for (const SpecularSample& x : samples) {
      if (x.r_p > 0.0f) ++begin_[(k++ / kChunk) * R + static_cast<std::size_t>(x.roughness) + 1];
    }
    for (std::size_t g = 0; g + 1 < begin_.size(); ++g) begin_[g + 1] += begin_[g];
    inputs_.resize(n);
    std::vector<std::size_t> next(begin_.begin(), begin_.end() - 1);
    k = 0;
    for (const SpecularSample& x : samples) {
      if (x.r_p > 0.0f) {
        inputs_[next[(k++ / kChunk) * R + static_cast<std::size_t>(x.roughness)]++] = coneInput(x);
      }
    }
  }
  const std::vector<float>& roughness() const { return roughness_; }

  bool wanted(std::size_t j, double rp_min) const {
    return roughness_[j] > 0.0f && roughness_[j] >= rp_min - 1e-9;
  }

  // Samples of the roughness values >= rp_min: what every SSE of that subset sums over.
  std::size_t count(double rp_min) const {
    const std::size_t R = roughness_.size();
    std::size_t n = 0;
    for (std::size_t g = 0; g + 1 < begin_.size(); ++g) {
      n += wanted(g % R, rp_min) ? begin_[g + 1] - begin_[g] : 0;
    }
    return n;
  }

  // Computes the SSE at every u of `us` for the roughness values >= rp_min not yet in the cache,
  // in one pass over the samples; each (u, roughness) is still summed chunk by chunk in sample
  // order, so its bits are those of a pass of its own.
  void prepare(const std::vector<double>& us, double rp_min) {
    const std::size_t R = roughness_.size();
    std::vector<double> batch;
    std::vector<std::vector<char>> todo;
    std::vector<std::vector<ConeAperture>> apertures;
    for (double u : us) {
      std::vector<Entry>& entry = cache_[u];
      if (entry.empty()) entry.assign(R, Entry{});
      std::vector<char> want(R, 0);
      bool any = false;
      for (std::size_t j = 0; j < R; ++j) {
        want[j] = wanted(j, rp_min) && !entry[j].done;
        any = any || want[j];
      }
      if (!any || std::find(batch.begin(), batch.end(), u) != batch.end()) continue;
      batch.push_back(u);
      todo.push_back(want);
      apertures.emplace_back();
      for (float r : roughness_) {
        apertures.back().push_back(coneAperture(u, perceptual_ ? r : static_cast<double>(r) * r));
      }
    }
    if (batch.empty()) return;
    const std::size_t B = batch.size();
    std::vector<std::vector<Entry>> partial(chunks_, std::vector<Entry>(B * R));
    tbb::parallel_for(std::size_t{0}, chunks_, [&](std::size_t c) {
      for (std::size_t j = 0; j < R; ++j) {
        const std::size_t first = begin_[c * R + j], last = begin_[c * R + j + 1];
        for (std::size_t b = 0; b < B; ++b) {
          if (!todo[b][j]) continue;
          const ConeAperture& aperture = apertures[b][j];
          double sse = 0.0;
          for (std::size_t k = first; k < last; ++k) {
            const double d = coneAt(inputs_[k], aperture) - inputs_[k].truth;
            sse += d * d;
          }
          partial[c][b * R + j].sse = sse;
          partial[c][b * R + j].count = last - first;
        }
      }
    });
    for (std::size_t b = 0; b < B; ++b) {
      std::vector<Entry>& entry = cache_[batch[b]];
      for (std::size_t j = 0; j < R; ++j) {
        if (!todo[b][j]) continue;
        for (const auto& p : partial) {
          entry[j].sse += p[b * R + j].sse;
          entry[j].count += p[b * R + j].count;
        }
        entry[j].done = true;
      }
    }
  }

  // [roughness index] -> (SSE, count) at u; the roughness values below rp_min keep count 0 until
  // asked for.
  const std::vector<Entry>& perRoughness(double u, double rp_min) {
    prepare({u}, rp_min);
    return cache_[u];
  }

 private:
  bool perceptual_;
  std::vector<float> roughness_;
  std::size_t chunks_ = 0;
  std::vector<ConeInput> inputs_;   // the samples with r_p > 0, by chunk, then roughness
  std::vector<std::size_t> begin_;  // [chunk * R + roughness]: where its group starts in inputs_
  std::map<double, std::vector<Entry>> cache_;
};

// The subset's SSE as a smooth function of z from the cone SSE table (u_scene_interval.h): the
// table summed over clusters and the subset's roughness values on its log10 u grid, between grid
// values the cubic Hermite curve with finite-difference slopes. It only guides the search (the
// scan, the bisections' path); every reported number is an exact SSE.
class SseModel {
 public:
  SseModel(const ConeSseTable& t, int law, const std::vector<float>& roughness, double rp_min)
      : x_(t.log10_u), y_(x_.size(), 0.0) {
    for (const auto& cluster : t.sse[law]) {
      for (std::size_t j = 0; j < cluster.size(); ++j) {
        if (j >= roughness.size() || !(roughness[j] > 0.0f && roughness[j] >= rp_min - 1e-9)) {
          continue;
        }
        for (std::size_t k = 0; k < y_.size(); ++k) y_[k] += cluster[j][k];
      }
    }
  }
  const std::vector<double>& z() const { return x_; }
  const std::vector<double>& sse() const { return y_; }
  double operator()(double z) const {
    const std::size_t n = x_.size();
    const auto k = static_cast<std::size_t>(
        std::clamp<std::ptrdiff_t>(std::upper_bound(x_.begin(), x_.end(), z) - x_.begin() - 1, 0,
                                   static_cast<std::ptrdiff_t>(n) - 2));
    const double h = x_[k + 1] - x_[k], t = std::clamp((z - x_[k]) / h, 0.0, 1.0);
    auto slope = [&](std::size_t i) {
      const std::size_t a = i == 0 ? 0 : i - 1, b = i + 1 == n ? i : i + 1;
      return (y_[b] - y_[a]) / (x_[b] - x_[a]);
    };
    const double t2 = t * t, t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * y_[k] + (t3 - 2 * t2 + t) * h * slope(k) +
           (-2 * t3 + 3 * t2) * y_[k + 1] + (t3 - t2) * h * slope(k + 1);
  }

 private:
  std::vector<double> x_, y_;
};

struct Subset {
  Objective* objective;
  double rp_min;
  const SseModel* model = nullptr;  // optional
};

std::pair<double, std::size_t> sseAndCount(const Subset& s, double u) {
  const auto& per = s.objective->perRoughness(u, s.rp_min);
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t j = 0; j < per.size(); ++j) {
    const float r = s.objective->roughness()[j];
    if (r > 0.0f && r >= s.rp_min - 1e-9) {
      sum += per[j].sse;
      count += per[j].count;
    }
  }
  return {sum, count};
}

double sse(const Subset& s, double u) {
  return sseAndCount(s, u).first;
}

double rmseAt(const Subset& s, double u) {
  const auto [sum, count] = sseAndCount(s, u);
  return count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

// The ends of the profile interval, bisected from z (inside: RMSE ≤ bound) towards z_low and
// z_high side by side (one pass over the samples per step for both); an open side is skipped.
std::pair<double, double> bisect(const Subset& s, double z, double z_low, double z_high,
                                 bool low_open, bool high_open, double bound) {
  double in[2] = {z, z}, out[2] = {z_low, z_high};
  const bool open[2] = {low_open, high_open};
  for (int i = 0; i < kBisections; ++i) {
    std::vector<double> us;
    for (int side = 0; side < 2; ++side) {
      if (!open[side]) us.push_back(std::pow(10.0, 0.5 * (in[side] + out[side])));
    }
    s.objective->prepare(us, s.rp_min);
    for (int side = 0; side < 2; ++side) {
      if (open[side]) continue;
      const double mid = 0.5 * (in[side] + out[side]);
      (rmseAt(s, std::pow(10.0, mid)) <= bound ? in[side] : out[side]) = mid;
    }
  }
  return {low_open ? z_low : in[0], high_open ? z_high : in[1]};
}

// bisect() with the model deciding each step where its RMSE is farther than kModelMargin from the
// bound and exact SSEs (both sides in one pass) where it is not, checked with exact SSEs where it
// ended: with an RMSE monotone on each side of the optimum (the bisection's own premise), the path
// is the exact bisection's when its last inside point is inside and its last outside point
// outside; otherwise that side's exact bisection runs.
std::pair<double, double> modelBisect(const Subset& s, double z, bool low_open, bool high_open,
                                      double bound, std::size_t count) {
  const double ends[2] = {kLog10UMin, kLog10UMax};
  const bool open[2] = {low_open, high_open};
  double in[2] = {z, z}, out[2] = {ends[0], ends[1]};
  auto modelRmse = [&](double zz) {
    return std::sqrt((*s.model)(zz) / static_cast<double>(count));
  };
  for (int i = 0; i < kBisections; ++i) {
    std::vector<double> exact;
    for (int side = 0; side < 2; ++side) {
      const double mid = 0.5 * (in[side] + out[side]);
      if (!open[side] && std::abs(modelRmse(mid) - bound) <= kModelMargin * bound) {
        exact.push_back(std::pow(10.0, mid));
      }
    }
    s.objective->prepare(exact, s.rp_min);
    for (int side = 0; side < 2; ++side) {
      if (open[side]) continue;
      const double mid = 0.5 * (in[side] + out[side]);
      const bool uncertain = std::abs(modelRmse(mid) - bound) <= kModelMargin * bound;
      ((uncertain ? rmseAt(s, std::pow(10.0, mid)) : modelRmse(mid)) <= bound ? in[side]
                                                                              : out[side]) = mid;
    }
  }
  std::vector<double> check;
  for (int side = 0; side < 2; ++side) {
    if (!open[side])
      check.insert(check.end(), {std::pow(10.0, in[side]), std::pow(10.0, out[side])});
  }
  s.objective->prepare(check, s.rp_min);
  bool redo[2] = {false, false};
  for (int side = 0; side < 2; ++side) {
    if (open[side]) continue;
    const bool in_ok = rmseAt(s, std::pow(10.0, in[side])) <= bound;
    const bool out_ok = out[side] == ends[side] || rmseAt(s, std::pow(10.0, out[side])) > bound;
    redo[side] = !in_ok || !out_ok;
  }
  if (redo[0] || redo[1]) {
    const auto exact = bisect(s, z, ends[0], ends[1], !redo[0], !redo[1], bound);
    if (redo[0]) in[0] = exact.first;
    if (redo[1]) in[1] = exact.second;
  }
  return {low_open ? ends[0] : in[0], high_open ? ends[1] : in[1]};
}

// The minimum of the SSE in z within one scan step of the best scan point z: golden-section
// search down to kGoldenWidth decades (the SSE is unimodal at that scale), then parabolas through
// (z − h, z, z + h) for h = kGoldenWidth / 2 down to kRefineFinest (three SSEs per pass over the
// samples; the sum over millions of pixels is smooth and near-quadratic at every such h), each
// vertex kept within 2h of z.
double minimise(const Subset& s, double z, double step) {
  auto at = [&](double zz) { return sse(s, std::pow(10.0, zz)); };
  const double invphi = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = std::max(kLog10UMin, z - step), b = std::min(kLog10UMax, z + step);
  double x1 = b - invphi * (b - a), x2 = a + invphi * (b - a);
  s.objective->prepare({std::pow(10.0, x1), std::pow(10.0, x2)}, s.rp_min);
  double f1 = at(x1), f2 = at(x2);
  while (b - a > kGoldenWidth) {
    if (f1 < f2) {
      b = x2, x2 = x1, f2 = f1;
      x1 = b - invphi * (b - a), f1 = at(x1);
    } else {
      a = x1, x1 = x2, f1 = f2;
      x2 = a + invphi * (b - a), f2 = at(x2);
    }
  }
  z = f1 < f2 ? x1 : x2;
  for (double h = 0.5 * kGoldenWidth; h >= kRefineFinest; h *= 0.1) {
    const double lo = std::max(kLog10UMin, z - h), hi = std::min(kLog10UMax, z + h);
    s.objective->prepare({std::pow(10.0, lo), std::pow(10.0, z), std::pow(10.0, hi)}, s.rp_min);
    const double fa = at(lo), fb = at(z), fc = at(hi);
    // The vertex of the parabola through (lo, fa), (z, fb), (hi, fc); p − q < 0 exactly when it
    // opens upwards (its second divided difference is −(p − q) / ((z − lo)(hi − z))).
    const double p = (z - lo) * (fb - fc), q = (z - hi) * (fb - fa);
    const double next = p - q < 0.0 ? z - ((z - lo) * p - (z - hi) * q) / (2.0 * (p - q))
                                    : (fa < fb && fa <= fc ? lo : (fc < fb ? hi : z));
    z = std::clamp(std::clamp(next, z - 2.0 * h, z + 2.0 * h), kLog10UMin, kLog10UMax);
  }
  return z;
}

UFit fitSubset(const Subset& s) {
  UFit fit;
  fit.count = s.objective->count(s.rp_min);
  if (fit.count == 0) throw Error("validate-gtso: no pixels with r_p > 0 to fit u");
  // The best point of a scan, then the minimum within one scan step of it: the model's grid (the
  // cone SSE table's values) when there is one, else a coarse scan (one pass for every point).
  double z = kLog10UMin, step = (kLog10UMax - kLog10UMin) / kGridSteps;
  if (s.model) {
    const std::vector<double>& y = s.model->sse();
    z = s.model->z()[static_cast<std::size_t>(std::min_element(y.begin(), y.end()) - y.begin())];
    step = kUGridStep;
  } else {
    auto gridZ = [](int g) { return kLog10UMin + (kLog10UMax - kLog10UMin) * g / kGridSteps; };
    std::vector<double> grid;
    for (int g = 0; g <= kGridSteps; ++g) grid.push_back(std::pow(10.0, gridZ(g)));
    s.objective->prepare(grid, s.rp_min);
    double best = HUGE_VAL;
    for (int g = 0; g <= kGridSteps; ++g) {
      const double e = sse(s, std::pow(10.0, gridZ(g)));
      if (e < best) best = e, z = gridZ(g);
    }
  }
  z = minimise(s, z, step);
  fit.u = std::pow(10.0, z);
  s.objective->prepare({fit.u, gtso::kPaperU, gtso::kUludagU, std::pow(10.0, kLog10UMin),
                        std::pow(10.0, kLog10UMax)},
                       s.rp_min);
  fit.rmse = rmseAt(s, fit.u);
  fit.rmse_paper = rmseAt(s, gtso::kPaperU);
  fit.rmse_uludag = rmseAt(s, gtso::kUludagU);
  const double bound = kProfileTolerance * fit.rmse;
  fit.low_open = rmseAt(s, std::pow(10.0, kLog10UMin)) <= bound;
  fit.high_open = rmseAt(s, std::pow(10.0, kLog10UMax)) <= bound;
  const auto [low, high] =
      s.model ? modelBisect(s, z, fit.low_open, fit.high_open, bound, fit.count)
              : bisect(s, z, kLog10UMin, kLog10UMax, fit.low_open, fit.high_open, bound);
  fit.low = std::pow(10.0, low);
  fit.high = std::pow(10.0, high);
  return fit;
}

}  // namespace

UFits fitConeU(const std::vector<SpecularSample>& samples, bool perceptual,
               const ConeSseTable* table, Progress* progress) {
  Objective objective(samples, perceptual);
  UFits fits;
  UFit* out[2] = {&fits.all, &fits.rp_ge_0_3};
  const double rp_min[2] = {0.0, 0.3};
  for (int k = 0; k < 2; ++k) {
    std::optional<SseModel> model;
    if (table) model.emplace(*table, perceptual ? 1 : 0, objective.roughness(), rp_min[k]);
    *out[k] = fitSubset(Subset{&objective, rp_min[k], model ? &*model : nullptr});
    if (progress) progress->add(1);
  }
  return fits;
}

}  // namespace gtbake
