#include "fit/normal_equations.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace gtbake {

namespace {

// A Cholesky pivot below this fraction of its diagonal entry means TᵀST is singular to working
// precision (unitless; the cubic's S has condition ~1e5, its pivots stay above ~1e-3 of the
// diagonal).
constexpr long double kPivotFloor = 1e-6L;

}  // namespace

void accumulate(NormalEquations& sums, const double* w, const double* A,
                const std::vector<const double*>& G, std::size_t count) {
  const std::size_t M = G.size();
  if (sums.moment.size() < M) sums.moment.resize(M);
  std::vector<double> moment(3 * M);
  for (std::size_t begin = 0; begin < count; begin += kSumBlock) {
    const std::size_t end = std::min(count, begin + kSumBlock);
    // x = (A³, −A², A): w·xxᵀ holds ±wA², ±wA³, wA⁴, ±wA⁵, wA⁶ only; w·x·G = G·(wA³, −wA², wA).
    double p[7] = {};  // p[k] = Σ w A^k, k = 2..6
    std::fill(moment.begin(), moment.end(), 0.0);
    for (std::size_t i = begin; i < end; ++i) {
      const double a = A[i];
      const double q1 = w[i] * a, q2 = q1 * a, q3 = q2 * a, q4 = q3 * a;
      p[2] += q2;
      p[3] += q3;
      p[4] += q4;
      p[5] += q4 * a;
      p[6] += q4 * a * a;
      for (std::size_t j = 0; j < M; ++j) {
        const double g = G[j][i];
        moment[3 * j] += g * q3;
        moment[3 * j + 1] -= g * q2;
        moment[3 * j + 2] += g * q1;
      }
      sums.weight += w[i];
    }
    const long double gram[9] = {p[6], -p[5], p[4], -p[5], p[4], -p[3], p[4], -p[3], p[2]};
    for (int k = 0; k < 9; ++k) sums.gram[k] += gram[k];
    for (std::size_t j = 0; j < M; ++j) {
      for (int r = 0; r < 3; ++r) sums.moment[j][r] += moment[3 * j + r];
    }
  }
  sums.points += count;
}

NormalEquations& NormalEquations::operator+=(const NormalEquations& other) {
  for (int k = 0; k < 9; ++k) gram[k] += other.gram[k];
  if (moment.size() < other.moment.size()) moment.resize(other.moment.size());
  for (std::size_t j = 0; j < other.moment.size(); ++j) {
    for (int r = 0; r < 3; ++r) moment[j][r] += other.moment[j][r];
  }
  weight += other.weight;
  points += other.points;
  return *this;
}

NormalEquations NormalEquations::scaled(long double factor) const {
  NormalEquations out = *this;
  for (long double& g : out.gram) g *= factor;
  for (auto& m : out.moment) {
    for (long double& v : m) v *= factor;
  }
  out.weight *= factor;
  return out;
}

std::string weightingName(Weighting w) {
  switch (w) {
    case Weighting::kPixel:
      return "pixel";
    case Weighting::kView:
      return "view";
    case Weighting::kFlatA:
      return "flat-a";
  }
  return "";
}

Weighting parseWeighting(const std::string& name) {
  for (Weighting w : kWeightings) {
    if (weightingName(w) == name) return w;
  }
  throw Error("--weighting must be pixel, view or flat-a, not '" + name + "'");
}

std::vector<double> pointWeights(const SweepData& data, Weighting weighting) {
  const std::size_t n = data.points();
  std::vector<double> w(n, 1.0);
  if (weighting == Weighting::kView) {
    const double per_view = static_cast<double>(n) / static_cast<double>(data.scenes.size());
    for (const SweepScene& s : data.scenes) {
      const double value = per_view / static_cast<double>(s.end - s.begin);
      std::fill(w.begin() + static_cast<std::ptrdiff_t>(s.begin),
                w.begin() + static_cast<std::ptrdiff_t>(s.end), value);
    }
  } else if (weighting == Weighting::kFlatA) {
    std::vector<std::size_t> bin(n), count(kFlatABins, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const double a = std::clamp(data.full.A[i], 0.0, 1.0);
      bin[i] = std::min<std::size_t>(kFlatABins - 1, static_cast<std::size_t>(a * kFlatABins));
      ++count[bin[i]];
    }
    const auto occupied = static_cast<double>(
        std::count_if(count.begin(), count.end(), [](std::size_t c) { return c > 0; }));
    for (std::size_t i = 0; i < n; ++i) {
      w[i] = static_cast<double>(n) / (occupied * static_cast<double>(count[bin[i]]));
    }
  }
  return w;
}

std::vector<LevelStatistics> sceneStatistics(const SweepData& data,
                                             const std::vector<double>& weights) {
  const std::size_t M = data.albedos.size();
  std::vector<LevelStatistics> out(data.scenes.size());
  tbb::parallel_for(std::size_t{0}, data.scenes.size(), [&](std::size_t s) {
    // One block of points at a time, every level from it while it is in cache.
    std::vector<double> A(kSumBlock), G(M * kSumBlock);
    std::vector<const double*> g(M);
    for (std::size_t j = 0; j < M; ++j) g[j] = &G[j * kSumBlock];
    for (int l = 0; l < kLevels; ++l) out[s][l].moment.assign(M, {});
    for (std::size_t begin = data.scenes[s].begin; begin < data.scenes[s].end; begin += kSumBlock) {
      const std::size_t count = std::min(kSumBlock, data.scenes[s].end - begin);
      for (int l = 0; l < kLevels; ++l) {
        const double c = 0.5 * kLevelScale[l];
        for (std::size_t k = 0; k < count; ++k) {
          const std::size_t i = begin + k;
          A[k] = data.full.A[i] + c * (data.half[0].A[i] - data.half[1].A[i]);
        }
        for (std::size_t j = 0; j < M; ++j) {
          const double* full = data.full.G[j].data() + begin;
          const double* h0 = data.half[0].G[j].data() + begin;
          const double* h1 = data.half[1].G[j].data() + begin;
          for (std::size_t k = 0; k < count; ++k)
            G[j * kSumBlock + k] = full[k] + c * (h0[k] - h1[k]);
        }
        accumulate(out[s][l], weights.data() + begin, A.data(), g, count);
      }
    }
  });
  return out;
}

LevelStatistics sumScenes(const std::vector<LevelStatistics>& scenes,
                          const std::vector<bool>& include) {
  LevelStatistics total;
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    if (!include[s]) continue;
    for (int l = 0; l < kLevels; ++l) total[l] += scenes[s][l];
  }
  return total;
}

Cubic CubicParameterization::theta(const std::vector<double>& phi) const {
  Cubic out = t0;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < N; ++c) out[r] += T[r * N + c] * phi[c];
  }
  return out;
}

CubicParameterization freeCubic() {
  return {3, {1, 0, 0, 0, 1, 0, 0, 0, 1}, {0.0, 0.0, 0.0}};
}

CubicParameterization openConstrainedCubic() {
  // (a, b, c) = (φ0, φ1, 1 − φ0 + φ1): a − b + c = 1.
  return {2, {1, 0, 0, 1, -1, 1}, {0.0, 0.0, 1.0}};
}

ReducedProblem reduceProblem(const NormalEquations& s, std::size_t albedo,
                             const CubicParameterization& p) {
  const int N = p.N;
  // Reduced Gram TᵀST and right-hand side Tᵀ(b − S t0), in long double.
  std::vector<long double> gram(N * N, 0.0L), rhs(N, 0.0L);
  long double shifted[3];
  for (int r = 0; r < 3; ++r) {
    shifted[r] = s.moment[albedo][r];
    for (int c = 0; c < 3; ++c) shifted[r] -= s.gram[3 * r + c] * p.t0[c];
  }
  for (int u = 0; u < N; ++u) {
    for (int r = 0; r < 3; ++r) rhs[u] += p.T[r * N + u] * shifted[r];
    for (int v = 0; v < N; ++v) {
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
          gram[u * N + v] += p.T[r * N + u] * s.gram[3 * r + c] * p.T[c * N + v];
        }
      }
    }
  }
  // Cholesky gram = RᵀR, R upper triangular, then forward substitution Rᵀz = rhs.
  std::vector<long double> R(N * N, 0.0L), z(N, 0.0L);
  for (int i = 0; i < N; ++i) {
    long double d = gram[i * N + i];
    for (int k = 0; k < i; ++k) d -= R[k * N + i] * R[k * N + i];
    if (!(d > kPivotFloor * kPivotFloor * gram[i * N + i])) {
      throw Error(
          "the per-albedo cubic is not determined by the data (rank-deficient: too few "
          "distinct A)");
    }
    R[i * N + i] = std::sqrt(d);
    for (int j = i + 1; j < N; ++j) {
      long double e = gram[i * N + j];
      for (int k = 0; k < i; ++k) e -= R[k * N + i] * R[k * N + j];
      R[i * N + j] = e / R[i * N + i];
    }
    long double t = rhs[i];
    for (int k = 0; k < i; ++k) t -= R[k * N + i] * z[k];
    z[i] = t / R[i * N + i];
  }
  ReducedProblem out;
  out.R.assign(R.begin(), R.end());
  out.z.assign(z.begin(), z.end());
  return out;
}

}  // namespace gtbake
