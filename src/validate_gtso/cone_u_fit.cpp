#include "validate_gtso/cone_u_fit.h"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "common/error.h"

namespace gtbake {

namespace {

constexpr std::size_t kChunk = 4096;    // samples per reduction chunk: fixed, so the sum's order
                                        // (and its bits) does not depend on the thread count
constexpr int kGridSteps = 12;          // coarse scan of log10 u before Ceres
constexpr int kBisections = 12;         // profile-interval bisections per side: 12/2^12 decades
constexpr double kRelativeStep = 1e-6;  // NumericDiffOptions::relative_step_size's default
constexpr double kPaperU = 0.01;        // paper Eq. 26
constexpr double kUludagU = 0.244;      // Uludag 2014, quoted in the paper's Appendix B

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
    for (const SpecularSample& x : samples) {
      if (static_cast<std::size_t>(x.roughness) >= roughness_.size()) {
        roughness_.resize(x.roughness + 1, 0.0f);
      }
      roughness_[x.roughness] = x.r_p;
      if (x.r_p > 0.0f) {
        inputs_.push_back(coneInput(x));
        of_.push_back(x.roughness);
      }
    }
  }
  const std::vector<float>& roughness() const { return roughness_; }

  bool wanted(std::size_t j, double rp_min) const {
    return roughness_[j] > 0.0f && roughness_[j] >= rp_min - 1e-9;
  }

  // Samples of the roughness values >= rp_min: what every SSE of that subset sums over.
  std::size_t count(double rp_min) const {
    std::size_t n = 0;
    for (int j : of_) n += wanted(static_cast<std::size_t>(j), rp_min) ? 1 : 0;
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
    const std::size_t chunks = (inputs_.size() + kChunk - 1) / kChunk;
    std::vector<std::vector<Entry>> partial(chunks, std::vector<Entry>(B * R));
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
      const std::size_t end = std::min(inputs_.size(), (c + 1) * kChunk);
      for (std::size_t k = c * kChunk; k < end; ++k) {
        const auto j = static_cast<std::size_t>(of_[k]);
        for (std::size_t b = 0; b < B; ++b) {
          if (!todo[b][j]) continue;
          const double d = coneAt(inputs_[k], apertures[b][j]) - inputs_[k].truth;
          partial[c][b * R + j].sse += d * d;
          ++partial[c][b * R + j].count;
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
  std::vector<ConeInput> inputs_;  // the samples with r_p > 0, in sample order
  std::vector<int> of_;            // their roughness index
  std::map<double, std::vector<Entry>> cache_;
};

struct Subset {
  Objective* objective;
  double rp_min;
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

// One residual √SSE(10^z), which Ceres minimises the square of, with the Jacobian of Ceres'
// NumericDiffCostFunction<CENTRAL> (step max(√ε, 1e-6 |z|), the same operations in the same
// order, so the same iterates), its three points scored in one pass over the samples.
class RootSse : public ceres::SizedCostFunction<1, 1> {
 public:
  explicit RootSse(const Subset* subset) : subset_(subset) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double z = parameters[0][0];
    if (jacobians == nullptr || jacobians[0] == nullptr) {
      residuals[0] = std::sqrt(sse(*subset_, std::pow(10.0, z)));
      return true;
    }
    const double delta =
        std::max(std::sqrt(std::numeric_limits<double>::epsilon()), std::abs(z) * kRelativeStep);
    const double forward = z + delta, backward = z - delta;
    subset_->objective->prepare(
        {std::pow(10.0, z), std::pow(10.0, forward), std::pow(10.0, backward)}, subset_->rp_min);
    residuals[0] = std::sqrt(sse(*subset_, std::pow(10.0, z)));
    double slope = std::sqrt(sse(*subset_, std::pow(10.0, forward)));
    slope -= std::sqrt(sse(*subset_, std::pow(10.0, backward)));
    double one_over_delta = 1.0 / delta;
    one_over_delta /= 2;
    jacobians[0][0] = slope * one_over_delta;
    return true;
  }

 private:
  const Subset* subset_;
};

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

UFit fitSubset(const Subset& s) {
  UFit fit;
  fit.count = s.objective->count(s.rp_min);
  if (fit.count == 0) throw Error("validate-gtso: no pixels with r_p > 0 to fit u");
  // Coarse scan (one pass for every grid point), then Ceres from the best grid point (bounded
  // to the search range).
  auto gridZ = [](int g) { return kLog10UMin + (kLog10UMax - kLog10UMin) * g / kGridSteps; };
  std::vector<double> grid;
  for (int g = 0; g <= kGridSteps; ++g) grid.push_back(std::pow(10.0, gridZ(g)));
  s.objective->prepare(grid, s.rp_min);
  double z = kLog10UMin;
  double best = HUGE_VAL;
  for (int g = 0; g <= kGridSteps; ++g) {
    const double zg = gridZ(g);
    const double e = sse(s, std::pow(10.0, zg));
    if (e < best) {
      best = e;
      z = zg;
    }
  }
  ceres::Problem problem;
  problem.AddResidualBlock(new RootSse(&s), nullptr, &z);
  problem.SetParameterLowerBound(&z, 0, kLog10UMin);
  problem.SetParameterUpperBound(&z, 0, kLog10UMax);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.num_threads = 1;
  options.function_tolerance = 1e-10;
  options.parameter_tolerance = 1e-8;
  options.max_num_iterations = 50;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable()) {
    throw Error("validate-gtso: the u fit failed: " + summary.message);
  }
  fit.u = std::pow(10.0, z);
  s.objective->prepare(
      {fit.u, kPaperU, kUludagU, std::pow(10.0, kLog10UMin), std::pow(10.0, kLog10UMax)}, s.rp_min);
  fit.rmse = rmseAt(s, fit.u);
  fit.rmse_paper = rmseAt(s, kPaperU);
  fit.rmse_uludag = rmseAt(s, kUludagU);
  const double bound = kProfileTolerance * fit.rmse;
  fit.low_open = rmseAt(s, std::pow(10.0, kLog10UMin)) <= bound;
  fit.high_open = rmseAt(s, std::pow(10.0, kLog10UMax)) <= bound;
  const auto [low, high] = bisect(s, z, kLog10UMin, kLog10UMax, fit.low_open, fit.high_open, bound);
  fit.low = std::pow(10.0, low);
  fit.high = std::pow(10.0, high);
  return fit;
}

}  // namespace

UFits fitConeU(const std::vector<SpecularSample>& samples, bool perceptual, Progress* progress) {
  Objective objective(samples, perceptual);
  UFits fits;
  fits.all = fitSubset(Subset{&objective, 0.0});
  if (progress) progress->add(1);
  fits.rp_ge_0_3 = fitSubset(Subset{&objective, 0.3});
  if (progress) progress->add(1);
  return fits;
}

}  // namespace gtbake
