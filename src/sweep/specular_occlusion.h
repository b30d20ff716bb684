// True specular occlusion S at a surface point (docs/sweep.md §1, paper Eq. 14; docs/sweep.md §2):
//
//   S(x, ωo, r_p) = ∫_H V(x, ωi) fr(ωo, ωi) (n·ωi) dωi / ∫_H fr(ωo, ωi) (n·ωi) dωi,
//
// fr the GGX BRDF of docs/gtso.md §1 (α = r_p², height-correlated Smith G2, F = 1), ωo the unit
// direction from x to the camera, V the binary sky visibility within the sky radius R (the V of A).
// Near-field S_R (docs/sweep.md, "Near-field truth"): the same with V_R, where an occluder farther
// than the G-buffer radius R does not occlude; from the same samples, the occluded ones traced
// again up to the largest radius for their hit distance.
//
// Estimator. Visible normals wm ~ D_ωo(wm) = G1(ωo) max(0, ωo·wm) D(wm) / (n·ωo) (Heitz 2018),
// ωi = reflect(ωo, wm). Per sample, fr (n·ωi) / pdf(ωi) = G2(ωo, ωi) / G1(ωo) =: w ∈ [0, 1]
// (0 for ωi below the horizon, whose ray is not traced). Then
//   Ŝ = Σ V_s w_s / Σ w_s,
// a ratio of two unbiased estimates of numerator and denominator (both scaled by the same
// 1/N): V = 1 everywhere gives exactly 1, V = 0 exactly 0. Its bias is O(1/N) and by the delta
// method Var(Ŝ) ≈ E[w² (V − S)²] / (N E[w]²) ≤ S(1 − S)/N · E[w²]/E[w]². Each half (samples
// of one parity, N/2 draws stratified over a grid as the walks' first bounce, strata.h) gives
// its own ratio H0, H1; (H0 − H1)²/4 estimates Var(Ŝ) to first order.
//
// Mirror limit r_p = 0 (α = 0): S = V(ωr), ωr = reflect(ωo, n), one ray, both halves equal.
//
// Random numbers: roughness j's sample s draws (u0, u1) = words 0, 1 of Philox counter
// (s, kSpecularBlock + j) of the pixel's stream: blocks the walks (blocks ⌊k/2⌋ ≤ 8) never use.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sweep/cosine_direction.h"
#include "sweep/embree_tracer.h"
#include "sweep/escape_walk.h"

namespace gtbake {

inline constexpr std::uint32_t kSpecularBlock = 1u << 16;  // Philox block of roughness index 0

// The per-(pixel, roughness) constants of the VNDF sampler in the local frame (t, s, n) of the
// normal (tangentBasis): ωo, its stretched configuration Vh = normalize(α ωo.x, α ωo.y, ωo.z)
// and the frame (T1, T2) around it (gtso::GgxDistribution::sampleWm's), and 1/(1 + Λ(ωo)).
struct VndfFrame {
  float alpha = 0.0f;
  float alpha2 = 0.0f;
  float wo[3] = {0.0f, 0.0f, 1.0f};
  float vh[3] = {0.0f, 0.0f, 1.0f};
  float t1[3] = {1.0f, 0.0f, 0.0f};
  float t2[3] = {0.0f, 1.0f, 0.0f};
  float squash = 1.0f;                 // s = (1 + Vh.z)/2 of Heitz 2018
  float inv_one_plus_lambda_o = 1.0f;  // 1/(1 + Λ(ωo)); 0 at the horizon
};

// Built in double from α > 0 and the local ωo (ωo.z ≥ 0), then rounded to float.
VndfFrame makeVndfFrame(double alpha, const float wo_local[3]);

// Sample (u0, u1) ∈ [0,1)²: the local ωi = reflect(ωo, wm) of the visible normal wm, as
// gtso::GgxDistribution::sampleWi in float, and its weight G2(ωo, ωi)/G1(ωo) (0 below the
// horizon), as gtso::GgxDistribution::weight. Branch-free float, so loops over samples vectorize.
inline void vndfReflect(const VndfFrame& f, float u0, float u1, float wi[3], float* weight) {
  float p1;
  float p2;
  concentricDisk(u0, u1, &p1, &p2);
  const float h = 1.0f - p1 * p1;
  const float t2 = (1.0f - f.squash) * __builtin_sqrtf(h > 0.0f ? h : 0.0f) + f.squash * p2;
  const float z2 = h - t2 * t2;
  const float tz = __builtin_sqrtf(z2 > 0.0f ? z2 : 0.0f);
  float m[3];
  for (int c = 0; c < 3; ++c) m[c] = p1 * f.t1[c] + t2 * f.t2[c] + tz * f.vh[c];
  m[0] *= f.alpha;
  m[1] *= f.alpha;
  m[2] = m[2] > 0.0f ? m[2] : 0.0f;
  const float len2 = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
  const float inv = len2 > 0.0f ? 1.0f / __builtin_sqrtf(len2) : 0.0f;
  for (float& v : m) v *= inv;
  const float d = 2.0f * (f.wo[0] * m[0] + f.wo[1] * m[1] + f.wo[2] * m[2]);
  for (int c = 0; c < 3; ++c) wi[c] = d * m[c] - f.wo[c];
  // Λ(ωi) = x / (2(√(1 + x) + 1)), x = α² tan²θi (full precision at small α).
  const bool above = wi[2] > 0.0f;
  const float c2 = above ? wi[2] * wi[2] : 1.0f;
  const float s2 = 1.0f - c2;
  const float x = f.alpha2 * (s2 > 0.0f ? s2 : 0.0f) / c2;
  const float lambda = x / (2.0f * (__builtin_sqrtf(1.0f + x) + 1.0f));
  *weight = above ? 1.0f / (1.0f + lambda * f.inv_one_plus_lambda_o) : 0.0f;
}

// Per-thread buffers, reused from point to point.
struct SpecularScratch {
  std::vector<std::int32_t> sample;
  std::vector<std::uint32_t> words[4];
  std::vector<float> u[2];
  std::vector<float> cell[2];
  std::vector<float> direction[3];
  std::vector<float> weight;
  std::vector<std::int32_t> traced;  // sample of each ray slot
  std::vector<std::int32_t> again;   // slot of each ray traced again for its hit distance
  std::vector<float> hit_t;          // per slot: hit distance (∞ where the ray escaped)
  std::vector<RTCRayHit> rays;
};

// For every roughness j of settings.specular_roughness, traces settings.specular_spp samples from
// `start` (mirror: one ray) for the view direction wo (unit, world space, n·wo ≥ 0) and adds to
// sums[4j + 2h] Σ V·w and to sums[4j + 2h + 1] Σ w over the samples of half h (sample parity),
// in sample order. If near_sums is given, adds to near_sums[2(rJ + j) + h] (J roughness values)
// Σ V_R·w at G-buffer radius R_r = settings.gbuffer_radii[r] (its Σ w is the unbounded one).
// Returns the rays traced. Depends only on (start, wo, settings, stream).
std::uint64_t traceSpecular(const EmbreeTracer& tracer, const SurfaceHit& start, const float wo[3],
                            const WalkSettings& settings, std::uint64_t stream, double* sums,
                            SpecularScratch* scratch, double* near_sums = nullptr);

// Ŝ from a half's or the pooled sums Σ V·w, Σ w (1 when no sample had weight).
inline double specularRatio(double visible, double total) {
  return total > 0.0 ? visible / total : 1.0;
}

// Each r_p in [0, 1], channel names distinct, spp even in [2, 2^16] unless the list is empty.
void validateSpecularOptions(const std::vector<double>& roughness, int spp);
// "0.1,0.25,..." (%.9g each), or "none".
std::string specularRoughnessList(const std::vector<double>& roughness);

}  // namespace gtbake
