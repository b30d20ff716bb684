// `gtao-reference`: GTAO as the paper (Eqs. 5–8) and the technical memo (Alg. 1, 2) define it,
// run to convergence: exact horizons (exactHorizonCos: every texel the slice's line crosses within
// the radius, each at its highest valid point), the analytic cosine-weighted slice integral with
// the projected-normal term and Alg. 2's bent normal, integrated over the directions about V by
// the trapezoid rule on 2·slices even directions, bisected where a horizon jumps
// (docs/screen_ao.md, "gtao-reference").
#pragma once

#include <vector>

#include "screen_ao/estimate.h"

namespace gtbake {

struct GtaoReferenceSettings {
  double radius = 1.0;  // metres: samples farther from P than this are ignored
  int slices = 32;      // base grid: 2·slices directions φ_k = π(k + ½)/slices about V
  // An interval [a, b] of directions is bisected while (b − a)·|F(b) − F(a)| exceeds this (F the
  // direction's visibility term, so a jump of F inside costs at most half of it), at most
  // refine_levels times.
  double refine_tolerance = 0.008;
  int refine_levels = 8;
};

// Throws gtbake::Error naming the bad setting.
void validate(const GtaoReferenceSettings& s);

AoEstimate gtaoReference(const GBuffer& g, const GtaoReferenceSettings& s);

// One pixel (view-space Â and unnormalised bent normal), for tests and the convergence check.
void gtaoReferencePixel(const GBuffer& g, int i, int j, const GtaoReferenceSettings& s, double* a,
                        Eigen::Vector3d* bent);

}  // namespace gtbake

namespace gtbake {

// Convergence evidence: Â at s and at the doubled discretisation (twice the slices, half the
// refine tolerance, one more refine level; the horizon search itself is exact), on every 8th pixel
// of every 8th row of every image (1 in 64 of the pixels, where unmasked).
struct ReferenceConvergence {
  GtaoReferenceSettings settings;
  GtaoReferenceSettings doubled;
  std::size_t pixels = 0;
  double rms_change = 0.0;
  double max_change = 0.0;
};

inline constexpr int kConvergenceStride = 8;
inline constexpr double kConvergenceBar = 0.002;  // RMS change that counts as converged

ReferenceConvergence referenceConvergence(const std::vector<const GBuffer*>& images,
                                          const GtaoReferenceSettings& s);

}  // namespace gtbake
