#include "screen_ao/visibility_bitmask.h"

#include <bitset>

#include "common/error.h"
#include "screen_ao/slice_geometry.h"

namespace gtbake {

namespace {

// The open slice's cosine-weighted mass ∫ over [n − π/2, n + π/2] of cos(θ − n)|sin θ| dθ.
double openMass(double n) {
  return arcIntegral(n + 0.5 * kPi, n) + arcIntegral(n - 0.5 * kPi, n);
}

// ∫ from n − π/2 to θ of cos(x − n)|sin x| dx (arcIntegral is the signed mass from 0).
double cumulativeMass(double theta, double n) {
  const double below = arcIntegral(n - 0.5 * kPi, n);
  return theta <= 0.0 ? below - arcIntegral(theta, n) : below + arcIntegral(theta, n);
}

// The slice angle of sector coordinate u (inverse of sectorCoordinate), by bisection.
double sectorAngle(double u, double n, SectorWeights weights) {
  const double lo0 = n - 0.5 * kPi;
  if (weights == SectorWeights::kUniform) return lo0 + kPi * u;
  double lo = lo0;
  double hi = n + 0.5 * kPi;
  for (int k = 0; k < 48; ++k) {
    const double mid = 0.5 * (lo + hi);
    (sectorCoordinate(mid, n, weights) < u ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// ∫ over [θa, θb] of cos(θ − n)|sin θ| (sin θ, cos θ) dθ: differences of Alg. 2's one-side terms.
void bentOver(double a, double b, double n, double* t0, double* t1) {
  double a0 = 0.0, a1 = 0.0, b0 = 0.0, b1 = 0.0;
  bentIntegrals(0.0, a, n, &a0, &a1);
  bentIntegrals(0.0, b, n, &b0, &b1);
  const double sa = a < 0.0 ? -1.0 : 1.0;  // bentIntegrals(0, h) is the mass over [h, 0] for h < 0
  const double sb = b < 0.0 ? -1.0 : 1.0;
  *t0 = sb * b0 - sa * a0;
  *t1 = sb * b1 - sa * a1;
}

// One slice's 32 sectors from both sides' samples.
std::uint32_t sliceBits(const GBuffer& g, int i, int j, const Eigen::Vector3d& x,
                        const Eigen::Vector3d& v, const Slice& slice, double radius_px,
                        const BitmaskSettings& s) {
  std::uint32_t bits = 0;
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? -1.0 : 1.0;
    for (int step = 0; step < s.steps; ++step) {
      const double t = sign * (step + 0.5) / s.steps * radius_px;
      Eigen::Vector3d sample;
      if (!texelPoint(g, i + 0.5 + t * slice.omega.x(), j + 0.5 - t * slice.omega.y(), &sample)) {
        continue;
      }
      const Eigen::Vector3d front = sample - x;
      const double length = front.norm();
      if (length > s.radius || !(length > 0.0)) continue;
      const Eigen::Vector3d back = front - s.thickness * v;
      const double theta_f = sign * std::acos(std::clamp(front.dot(v) / length, -1.0, 1.0));
      const double theta_b = sign * std::acos(std::clamp(back.normalized().dot(v), -1.0, 1.0));
      bits |= sectorBits(sectorCoordinate(theta_f, slice.n, s.weights),
                         sectorCoordinate(theta_b, slice.n, s.weights));
    }
  }
  return bits;
}

void bitmaskPixel(const GBuffer& g, int i, int j, std::size_t p, const BitmaskSettings& s,
                  double* a, Eigen::Vector3d* bent) {
  const Eigen::Vector3d x = viewPosition(g, p);
  const Eigen::Vector3d v = -x.normalized();
  const Eigen::Vector3d normal = viewNormal(g, p);
  const double radius_px = s.radius * g.pixelsPerMetre(g.depth[p]);
  double visibility = 0.0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int k = 0; k < s.slices; ++k) {
    const Slice slice = makeSlice(v, normal, kPi * (k + 0.5) / s.slices);
    const std::uint32_t bits = sliceBits(g, i, j, x, v, slice, radius_px, s);
    const double clear = 1.0 - static_cast<double>(std::bitset<32>(bits).count()) / kSectors;
    visibility += s.weights == SectorWeights::kUniform
                      ? clear
                      : slice.projected_length * openMass(slice.n) * clear;
    for (int run = 0; run < kSectors;) {  // each run of clear sectors
      if ((bits >> run) & 1u) {
        ++run;
        continue;
      }
      int end = run;
      while (end < kSectors && !((bits >> end) & 1u)) ++end;
      double t0 = 0.0;
      double t1 = 0.0;
      bentOver(sectorAngle(static_cast<double>(run) / kSectors, slice.n, s.weights),
               sectorAngle(static_cast<double>(end) / kSectors, slice.n, s.weights), slice.n, &t0,
               &t1);
      sum += slice.projected_length * (t0 * slice.o + t1 * v);
      run = end;
    }
  }
  *a = visibility / s.slices;
  *bent = sum;
}

}  // namespace

double sectorCoordinate(double theta, double n, SectorWeights weights) {
  const double clamped = std::clamp(theta, n - 0.5 * kPi, n + 0.5 * kPi);
  if (weights == SectorWeights::kUniform) return (clamped - n + 0.5 * kPi) / kPi;
  return std::clamp(cumulativeMass(clamped, n) / openMass(n), 0.0, 1.0);
}

std::uint32_t sectorBits(double ua, double ub) {
  const double lo = std::clamp(std::min(ua, ub), 0.0, 1.0);
  const double hi = std::clamp(std::max(ua, ub), 0.0, 1.0);
  const int start = std::min(kSectors - 1, static_cast<int>(std::floor(lo * kSectors)));
  const int count = static_cast<int>(std::ceil((hi - lo) * kSectors));
  if (count <= 0) return 0u;
  const std::uint32_t run = count >= kSectors ? 0xffffffffu : (1u << count) - 1u;
  return run << start;
}

void validate(const BitmaskSettings& s) {
  const std::string name =
      s.weights == SectorWeights::kUniform ? "bitmask-uniform" : "bitmask-cosine";
  if (!(s.radius > 0.0) || !std::isfinite(s.radius)) {
    throw Error(name + ": radius must be a positive finite distance in metres");
  }
  if (s.slices < 1 || s.slices > 1024) throw Error(name + ": slices must be in [1, 1024]");
  if (s.steps < 1 || s.steps > 4096) throw Error(name + ": steps must be in [1, 4096]");
  if (!(s.thickness > 0.0) || !std::isfinite(s.thickness)) {
    throw Error(name + ": thickness must be a positive finite distance in metres");
  }
}

AoEstimate visibilityBitmask(const GBuffer& g, const BitmaskSettings& s) {
  validate(s);
  return estimatePerPixel(g, [&](int i, int j, std::size_t p, double* a, Eigen::Vector3d* bent) {
    bitmaskPixel(g, i, j, p, s, a, bent);
  });
}

}  // namespace gtbake
