#include "validate_gtso/cone_u_fit.h"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "common/error.h"

namespace gtbake {

namespace {

constexpr std::size_t kChunk = 4096;  // samples per reduction chunk: fixed, so the sum's order
                                      // (and its bits) does not depend on the thread count
constexpr int kGridSteps = 12;        // coarse scan of log10 u before Ceres
constexpr int kBisections = 12;       // profile-interval bisections per side: 12/2^12 decades

// Per-roughness SSE of S_cone(u) over every sample with r_p > 0, memoised by u: both subsets
// (all r_p, r_p ≥ 0.3) of one convention share the grid and the fixed-u evaluations.
class Objective {
 public:
  struct Entry {
    double sse = 0.0;
    std::size_t count = 0;
    bool done = false;
  };

  Objective(const std::vector<SpecularSample>& samples, bool perceptual)
      : samples_(&samples), perceptual_(perceptual) {
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const SpecularSample& x = samples[i];
      if (static_cast<std::size_t>(x.roughness) >= roughness_.size()) {
        roughness_.resize(x.roughness + 1, 0.0f);
      }
      roughness_[x.roughness] = x.r_p;
      if (x.r_p > 0.0f) index_.push_back(i);
    }
  }
  const std::vector<float>& roughness() const { return roughness_; }

  // [roughness index] -> (SSE, count) at u, computed for the roughness values ≥ rp_min not yet
  // in the cache (the others keep count 0 until asked for).
  const std::vector<Entry>& perRoughness(double u, double rp_min) {
    std::vector<Entry>& entry = cache_[u];
    if (entry.empty()) entry.assign(roughness_.size(), Entry{});
    std::vector<char> wanted(roughness_.size(), 0);
    bool any = false;
    for (std::size_t j = 0; j < roughness_.size(); ++j) {
      wanted[j] = roughness_[j] > 0.0f && roughness_[j] >= rp_min - 1e-9 && !entry[j].done;
      any = any || wanted[j];
    }
    if (!any) return entry;
    std::vector<ConeAperture> apertures;
    for (float r : roughness_) {
      apertures.push_back(coneAperture(u, perceptual_ ? r : static_cast<double>(r) * r));
    }
    const std::size_t chunks = (index_.size() + kChunk - 1) / kChunk;
    std::vector<std::vector<Entry>> partial(chunks, std::vector<Entry>(roughness_.size()));
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
      const std::size_t end = std::min(index_.size(), (c + 1) * kChunk);
      for (std::size_t k = c * kChunk; k < end; ++k) {
        const SpecularSample& x = (*samples_)[index_[k]];
        if (!wanted[x.roughness]) continue;
        const double d = coneAt(x, apertures[x.roughness]) - x.truth;
        partial[c][x.roughness].sse += d * d;
        ++partial[c][x.roughness].count;
      }
    });
    for (std::size_t j = 0; j < roughness_.size(); ++j) {
      if (!wanted[j]) continue;
      for (const auto& p : partial) {
        entry[j].sse += p[j].sse;
        entry[j].count += p[j].count;
      }
      entry[j].done = true;
    }
    return entry;
  }

 private:
  const std::vector<SpecularSample>* samples_;
  bool perceptual_;
  std::vector<float> roughness_;
  std::vector<std::size_t> index_;
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

// One residual √SSE(10^z): Ceres minimises its square, the SSE.
struct RootSse {
  const Subset* subset;
  bool operator()(const double* z, double* residual) const {
    residual[0] = std::sqrt(sse(*subset, std::pow(10.0, z[0])));
    return true;
  }
};

// The end of the profile interval between z_in (inside: RMSE ≤ bound) and z_out.
double bisect(const Subset& s, double z_in, double z_out, double bound) {
  for (int i = 0; i < kBisections; ++i) {
    const double mid = 0.5 * (z_in + z_out);
    (rmseAt(s, std::pow(10.0, mid)) <= bound ? z_in : z_out) = mid;
  }
  return z_in;
}

UFit fitSubset(const Subset& s) {
  UFit fit;
  fit.count = sseAndCount(s, 0.5).second;
  if (fit.count == 0) throw Error("validate-gtso: no pixels with r_p > 0 to fit u");
  // Coarse scan, then Ceres from the best grid point (bounded to the search range).
  double z = kLog10UMin;
  double best = HUGE_VAL;
  for (int g = 0; g <= kGridSteps; ++g) {
    const double zg = kLog10UMin + (kLog10UMax - kLog10UMin) * g / kGridSteps;
    const double e = sse(s, std::pow(10.0, zg));
    if (e < best) {
      best = e;
      z = zg;
    }
  }
  ceres::Problem problem;
  problem.AddResidualBlock(
      new ceres::NumericDiffCostFunction<RootSse, ceres::CENTRAL, 1, 1>(new RootSse{&s}), nullptr,
      &z);
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
  fit.rmse = rmseAt(s, fit.u);
  fit.rmse_paper = rmseAt(s, 0.01);
  fit.rmse_uludag = rmseAt(s, 0.244);
  const double bound = kProfileTolerance * fit.rmse;
  fit.low_open = rmseAt(s, std::pow(10.0, kLog10UMin)) <= bound;
  fit.high_open = rmseAt(s, std::pow(10.0, kLog10UMax)) <= bound;
  fit.low = std::pow(10.0, fit.low_open ? kLog10UMin : bisect(s, z, kLog10UMin, bound));
  fit.high = std::pow(10.0, fit.high_open ? kLog10UMax : bisect(s, z, kLog10UMax, bound));
  return fit;
}

}  // namespace

UFits fitConeU(const std::vector<SpecularSample>& samples, bool perceptual) {
  Objective objective(samples, perceptual);
  UFits fits;
  fits.all = fitSubset(Subset{&objective, 0.0});
  fits.rp_ge_0_3 = fitSubset(Subset{&objective, 0.3});
  return fits;
}

}  // namespace gtbake
