// GTSO runtime lookup (docs/gtso.md §1, docs/export.md §2): the axis warps of the 3D and 4D
// tables and the texture reads a shader performs (BC4 decode, half-texel remap, trilinear filter,
// 4D tiles), for float32, BC4_UNORM, R16_UNORM and R8_UNORM texels; the cone-to-cone model, the
// multi-bounce fit and the profile tables' lookup.
//
// This file is the single C++ definition of the table axes: `gtbake gtso` bakes texel i of each
// axis at the inverse map of i/(N-1), the lookups here apply the forward map, and `gtbake export`
// copies this file verbatim into the generated gtbake_tables.h (so the shipped header carries
// exactly this tested code). gtso_runtime.shader is the HLSL/GLSL port, executed against
// this file by tests/shader. Self-contained C++17 (<cmath>, <cstdint>), namespace gtbake.
//
// Inputs: A (ambient occlusion, cos(alpha_v) = sqrt(1 - A), paper Eq. 18), cosBeta (cosine of the
// angle between the bent normal and the reflection vector wr), rp (perceptual roughness, GGX
// width alpha = rp^2) and, in 4D, cosThetaO (= n.wr). All angles below are in radians.
//
// clang-format off
// Axes (t in [0, 1]; texel i of N holds t = i/(N-1)). Two lobe scales (radians):
//   sigma  = kGtsoSigmaScale rp^2 + kGtsoSigmaFloor          (width of the mirror step in alpha_v)
//   lambda = kGtsoThetaLobeScale rp^2 + kGtsoThetaLobeFloor  (where theta_o and beta refine)
//   x, A axis, "step-warped": alpha_v = atan2(sqrt(A), sqrt(1 - A)), delta = alpha_v - s with
//     s = theta_o (3D) or beta (4D), spans P = sqrt(max(pi/2 - s, 0)^2 + c^2) above and
//     M = sqrt(s^2 + c^2) below the step, c = kGtsoSpanFloor:
//       t = tS + (1 - tS) asinh(delta / sigma) / asinh(P / sigma)   for delta >= 0,
//       t = tS - tS asinh(-delta / sigma) / asinh(M / sigma)        for delta < 0,
//     tS = floor((N-1)/2)/(N-1): the mirror step on texel tS for every s. The floor c keeps a
//     side from collapsing where the step meets an end of the A range (s -> 0, s -> pi/2); the
//     texels it adds beyond A = 0 and A = 1 hold the continuation of S in alpha_v (0 below,
//     the cap of half-angle alpha_v > pi/2 above), so interpolation across s stays smooth.
//   y, 3D: theta_o axis (below); 4D: beta in [0, theta_o + pi/2] (bent normals above the
//     horizon only), split at beta = theta_o on texel tB = floor(N/3)/(N-1) and refined at
//     beta = 0 (b on wr) on the scale lambda: with F(b) = wb b/(pi/2) + (1 - wb) asinh(b/lambda)
//     / asinh(pi/(2 lambda)), wb = kGtsoBetaLinear,
//       t = tB F(beta)/F(theta_o) below theta_o,
//       t = tB + (1 - tB)(F(beta) - F(theta_o))/(F(theta_o + pi/2) - F(theta_o)) above,
//     so S4(beta = theta_o) reads texels baked with b = n: the S3 values through the lookup.
//   z, r_p axis: t = sqrt(rp) (refined toward the mirror limit).
//   theta_o axis (3D y, 4D w), refined at normal view and at grazing on the scale lambda:
//       t = w x + (1 - w)(asinh(theta_o/lambda) - asinh((pi/2 - theta_o)/lambda) + L)/(2 L),
//     x = theta_o/(pi/2), L = asinh(pi/(2 lambda)), w = kGtsoThetaLinear.
//   The bake inverts the theta_o and beta maps by bisection (both strictly increasing).
// ALU beyond the fetches (asinh is a log and a sqrt in HLSL): A axis 1 atan2, 4 sqrt, 2 asinh,
// 3 div, ~12 mul/add; theta_o axis 1 acos, 3 asinh, 2 div, ~8; r_p axis 1 sqrt; 4D beta axis
// 1 acos, 3 asinh (L shared with theta_o), 3 div, ~10. Whole 3D lookup ~ 1 atan2, 1 acos,
// 5 asinh, 5 sqrt, 5 div, ~25 mul/add + 1 trilinear fetch; 4D ~ 1 atan2, 2 acos, 8 asinh,
// 5 sqrt, 8 div, ~45 mul/add + 2 trilinear fetches and a lerp.
// clang-format on
#ifndef GTBAKE_GTSO_LOOKUP_H
#define GTBAKE_GTSO_LOOKUP_H

#include <cmath>
#include <cstdint>

namespace gtbake {

// Axis constants, chosen by measurement (docs/gtso.md §3: end-to-end error on the selection
// seed 0, reported on seeds 1-3).
inline constexpr double kGtsoPi = 3.14159265358979323846;
inline constexpr double kGtsoSigmaScale = 1.0;       // sigma per GGX width alpha = rp^2
inline constexpr double kGtsoSigmaFloor = 1e-5;      // sigma at rp = 0
inline constexpr double kGtsoSpanFloor = 0.15;       // least span of a side of the step
inline constexpr double kGtsoThetaLobeScale = 0.25;  // lambda per alpha
inline constexpr double kGtsoThetaLobeFloor = 3e-3;  // lambda at rp = 0
inline constexpr double kGtsoThetaLinear = 0.4;      // linear share of the theta_o axis
inline constexpr double kGtsoBetaLinear = 0.5;       // linear share of the beta axis
inline constexpr double kGtsoRoughPower = 0.5;       // t = rp^power: < 1 refines r_p toward 0
// (sqrt: the lookups evaluate rp^0.5 as std::sqrt, the bake inverts with pow(t, 2))

// The axis constants by name: gtso.json's axis_constants keys (export refuses tables baked with
// other values) and the shader macros export defines from them.
struct GtsoAxisConstant {
  const char* key;
  const char* shaderMacro;
  double value;
};
inline constexpr GtsoAxisConstant kGtsoAxisConstants[] = {
    {"sigma_scale", "kGtsoSigmaScaleF", kGtsoSigmaScale},
    {"sigma_floor", "kGtsoSigmaFloorF", kGtsoSigmaFloor},
    {"span_floor", "kGtsoSpanFloorF", kGtsoSpanFloor},
    {"theta_lobe_scale", "kGtsoThetaLobeScaleF", kGtsoThetaLobeScale},
    {"theta_lobe_floor", "kGtsoThetaLobeFloorF", kGtsoThetaLobeFloor},
    {"theta_linear", "kGtsoThetaLinearF", kGtsoThetaLinear},
    {"beta_linear", "kGtsoBetaLinearF", kGtsoBetaLinear},
    {"rough_power", nullptr, kGtsoRoughPower}};  // rough_power: evaluated as sqrt in shaders

// The axes as gtso.json names them (x, y, z[, w]), their forward maps and ALU cost.
struct GtsoAxisInfo {
  const char* quantity;
  const char* forward;
  const char* alu;
};
// clang-format off
inline constexpr GtsoAxisInfo kGtsoAxisStepA = {
    "A_step_span",
    "alpha_v = atan2(sqrt(A), sqrt(1-A)); s = theta_o (3D) / beta (4D); sigma = kGtsoSigmaScale rp^2 + "
    "kGtsoSigmaFloor; P = sqrt(max(pi/2-s, 0)^2 + c^2), M = sqrt(s^2 + c^2), c = kGtsoSpanFloor; "
    "t = tS + (1-tS) asinh((alpha_v-s)/sigma)/asinh(P/sigma) above the step, "
    "tS - tS asinh((s-alpha_v)/sigma)/asinh(M/sigma) below; tS = floor((N-1)/2)/(N-1)",
    "1 atan2, 4 sqrt, 2 asinh, 3 div, ~12 mul/add"};
inline constexpr GtsoAxisInfo kGtsoAxisTheta = {
    "theta_o_lobe_ends",
    "theta_o = acos(cos theta_o); lambda = kGtsoThetaLobeScale rp^2 + kGtsoThetaLobeFloor; "
    "L = asinh(pi/(2 lambda)); t = w theta_o/(pi/2) + (1-w)(asinh(theta_o/lambda) - "
    "asinh((pi/2-theta_o)/lambda) + L)/(2 L), w = kGtsoThetaLinear",
    "1 acos, 3 asinh, 2 div, ~8 mul/add"};
inline constexpr GtsoAxisInfo kGtsoAxisRough = {"r_p_pow", "t = rp^kGtsoRoughPower", "1 sqrt"};
inline constexpr GtsoAxisInfo kGtsoAxisBeta = {
    "beta_lobe_split",
    "beta = acos(cosBeta) in [0, theta_o + pi/2] (bent normal above the horizon); F(b) = wb b/(pi/2) "
    "+ (1-wb) asinh(b/lambda)/asinh(pi/(2 lambda)), wb = kGtsoBetaLinear; t = tB F(beta)/F(theta_o) "
    "below theta_o, tB + (1-tB)(F(beta)-F(theta_o))/(F(theta_o+pi/2)-F(theta_o)) above; "
    "tB = floor(N/3)/(N-1)",
    "1 acos, 3 asinh (L shared with theta_o), 3 div, ~10 mul/add"};
// clang-format on
inline constexpr const GtsoAxisInfo* kGtso3DAxisInfo[3] = {&kGtsoAxisStepA, &kGtsoAxisTheta,
                                                           &kGtsoAxisRough};
inline constexpr const GtsoAxisInfo* kGtso4DAxisInfo[4] = {&kGtsoAxisStepA, &kGtsoAxisBeta,
                                                           &kGtsoAxisRough, &kGtsoAxisTheta};

// ---- axis maps, templated on float (runtime) and double (bake) ----

template <class T>
T gtsoClamp01(T x) {
  return x < T(0) ? T(0) : (x > T(1) ? T(1) : x);
}
template <class T>
T gtsoAcos(T x) {
  return std::acos(x < T(-1) ? T(-1) : (x > T(1) ? T(1) : x));
}
// Texel of the mirror step on the A axis and of beta = theta_o on the 4D beta axis, as t.
template <class T>
T gtsoStepT(int n) {
  return T((n - 1) / 2) / T(n - 1);
}
template <class T>
T gtsoBetaSplitT(int n) {
  return T(n / 3) / T(n - 1);
}
template <class T>
T gtsoSigma(T rp) {
  return T(kGtsoSigmaScale) * rp * rp + T(kGtsoSigmaFloor);
}
// The span of each side of the step on the A axis (radians of alpha_v from the step to the
// texel t = 1 above, t = 0 below): the distance to alpha_v = pi/2 (above) or 0 (below), floored
// smoothly at kGtsoSpanFloor so that no side collapses where the step meets an end of the A range
// (s -> pi/2, or s -> 0). Texels beyond the A range hold the continuation of S in alpha_v: 0 for
// alpha_v < 0 (an empty cone), the cap of half-angle alpha_v > pi/2 about b above (3D: S = 1).
template <class T>
T gtsoSpanAbove(T s) {
  const T d = T(kGtsoPi / 2) - s;
  const T c = T(kGtsoSpanFloor);
  return d > T(0) ? std::sqrt(d * d + c * c) : c;
}
template <class T>
T gtsoSpanBelow(T s) {
  const T c = T(kGtsoSpanFloor);
  return std::sqrt(s * s + c * c);
}
// alpha_v -> t and back, step s, width sigma, step texel tS (the inverse may leave [0, pi/2]:
// the continuation texels above).
template <class T>
T gtsoStepWarp(T alphaV, T s, T sigma, T tS) {
  if (alphaV >= s) {
    const T span = std::asinh(gtsoSpanAbove(s) / sigma);
    return tS + (T(1) - tS) * gtsoClamp01(std::asinh((alphaV - s) / sigma) / span);
  }
  const T span = std::asinh(gtsoSpanBelow(s) / sigma);
  return tS - tS * gtsoClamp01(std::asinh((s - alphaV) / sigma) / span);
}
template <class T>
T gtsoStepUnwarp(T t, T s, T sigma, T tS) {
  if (t >= tS) {
    const T span = std::asinh(gtsoSpanAbove(s) / sigma);
    return s + sigma * std::sinh(gtsoClamp01((t - tS) / (T(1) - tS)) * span);
  }
  const T span = std::asinh(gtsoSpanBelow(s) / sigma);
  return s - sigma * std::sinh(gtsoClamp01((tS - t) / tS) * span);
}
// theta_o axis, refined at both ends on the scale of the lobe: S depends on theta_o through
// theta_o / lambda at normal view and (pi/2 - theta_o) / lambda at grazing, lambda =
// kGtsoThetaLobeScale rp^2 + kGtsoThetaLobeFloor. Texel density w/(pi/2) + (1 - w)/2 (1/sqrt(
// theta_o^2 + lambda^2) + 1/sqrt(g^2 + lambda^2)) / asinh(pi/(2 lambda)), g = pi/2 - theta_o,
// integrated:
//   t = w x + (1 - w) (asinh(theta_o/lambda) - asinh(g/lambda) + L) / (2 L),
//   x = theta_o/(pi/2), L = asinh(pi/(2 lambda)), w = kGtsoThetaLinear,
// t(0) = 0, t(pi/2) = 1, strictly increasing; the bake inverts it by bisection.
template <class T>
T gtsoThetaLambda(T rp) {
  return T(kGtsoThetaLobeScale) * rp * rp + T(kGtsoThetaLobeFloor);
}
template <class T>
T gtsoThetaWarp(T thetaO, T rp) {
  const T halfPi = T(kGtsoPi / 2);
  const T th = thetaO < T(0) ? T(0) : (thetaO > halfPi ? halfPi : thetaO);
  const T lambda = gtsoThetaLambda(rp);
  const T L = std::asinh(halfPi / lambda);
  const T w = T(kGtsoThetaLinear);
  const T ends = (std::asinh(th / lambda) - std::asinh((halfPi - th) / lambda) + L) / (T(2) * L);
  return gtsoClamp01(w * th / halfPi + (T(1) - w) * ends);
}
// The x in [lo, hi] with warp(x) = t for a strictly increasing warp: bisection until the
// interval no longer splits in T (the bake's inverse of the theta_o and beta axes).
template <class T, class Warp>
T gtsoBisect(T lo, T hi, T t, const Warp& warp) {
  for (int k = 0; k < 200; ++k) {
    const T mid = T(0.5) * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (warp(mid) < t ? lo : hi) = mid;
  }
  return T(0.5) * (lo + hi);
}
template <class T>
T gtsoThetaUnwarp(T t, T rp) {
  const T halfPi = T(kGtsoPi / 2);
  if (t <= T(0)) return T(0);
  if (t >= T(1)) return halfPi;
  return gtsoBisect(T(0), halfPi, t, [rp](T x) { return gtsoThetaWarp(x, rp); });
}
// 4D beta axis over [0, theta_o + pi/2] (bent normals above the horizon), refined at beta = 0
// (b on the reflection vector) on the lobe scale lambda, split at beta = theta_o (b = n) on
// texel tB: with F(beta) = w beta/(pi/2) + (1 - w) asinh(beta/lambda)/asinh(pi/(2 lambda)),
// w = kGtsoBetaLinear,
//   t = tB F(beta)/F(theta_o)                                             below theta_o,
//   t = tB + (1 - tB)(F(beta) - F(theta_o))/(F(theta_o + pi/2) - F(theta_o))  above;
// the bake inverts it by bisection.
template <class T>
T gtsoBetaDensity(T beta, T rp) {
  const T halfPi = T(kGtsoPi / 2);
  const T lambda = gtsoThetaLambda(rp);
  const T w = T(kGtsoBetaLinear);
  return w * beta / halfPi + (T(1) - w) * std::asinh(beta / lambda) / std::asinh(halfPi / lambda);
}
template <class T>
T gtsoBetaWarp(T beta, T thetaO, T rp, T tB) {
  const T b = beta < T(0) ? T(0) : beta;
  const T fo = gtsoBetaDensity(thetaO, rp);
  const T f = gtsoBetaDensity(b, rp);
  if (b < thetaO) return tB * f / fo;  // b < thetaO implies fo > 0
  const T fe = gtsoBetaDensity(thetaO + T(kGtsoPi / 2), rp);
  return gtsoClamp01(tB + (T(1) - tB) * (f - fo) / (fe - fo));
}
template <class T>
T gtsoBetaUnwarp(T t, T thetaO, T rp, T tB) {
  T lo = t < tB ? T(0) : thetaO;
  T hi = t < tB ? thetaO : thetaO + T(kGtsoPi / 2);
  if (t <= T(0)) return T(0);
  if (t >= T(1)) return hi;
  return gtsoBisect(lo, hi, t, [&](T x) { return gtsoBetaWarp(x, thetaO, rp, tB); });
}

static_assert(kGtsoRoughPower == 0.5, "gtsoRoughWarp evaluates rp^kGtsoRoughPower as a sqrt");
template <class T>
T gtsoRoughWarp(T rp) {
  return std::sqrt(gtsoClamp01(rp));
}
template <class T>
T gtsoRoughUnwarp(T t) {
  return std::pow(gtsoClamp01(t), T(1) / T(kGtsoRoughPower));
}

// Physical parameters <-> axis positions t (logical order: A, beta, r_p, theta_o).
template <class T>
struct GtsoAxisT {
  T t[4];
};
template <class T>
struct GtsoPhysical {
  T A, beta, rp, thetaO;  // 3D: beta = theta_o
  T alphaV;               // the cone half-angle (gtsoTexelPhysical: may leave [0, pi/2])
};

// alpha_v from A: cos(alpha_v) = sqrt(1 - A) (paper Eq. 18), as atan2 for precision at both ends.
template <class T>
T gtsoAlphaV(T A) {
  const T a = gtsoClamp01(A);
  return std::atan2(std::sqrt(a), std::sqrt(T(1) - a));
}
template <class T>
GtsoAxisT<T> gtso3DAxes(T A, T cosBeta, T rp, const int* size) {
  const T alphaV = gtsoAlphaV(A);
  const T thetaO = gtsoAcos(cosBeta < T(0) ? T(0) : cosBeta);
  const T r = gtsoClamp01(rp);
  return {{gtsoStepWarp(alphaV, thetaO, gtsoSigma(r), gtsoStepT<T>(size[0])),
           gtsoThetaWarp(thetaO, r), gtsoRoughWarp(r), T(0)}};
}
template <class T>
GtsoAxisT<T> gtso4DAxes(T A, T cosBeta, T rp, T cosThetaO, const int* size) {
  const T alphaV = gtsoAlphaV(A);
  const T beta = gtsoAcos(cosBeta);
  const T thetaO = gtsoAcos(cosThetaO < T(0) ? T(0) : cosThetaO);
  const T r = gtsoClamp01(rp);
  return {{gtsoStepWarp(alphaV, beta, gtsoSigma(r), gtsoStepT<T>(size[0])),
           gtsoBetaWarp(beta, thetaO, r, gtsoBetaSplitT<T>(size[1])), gtsoRoughWarp(r),
           gtsoThetaWarp(thetaO, r)}};
}
// The cone half-angle of texel ia of n on the A axis, for step s = beta (3D: theta_o).
template <class T>
T gtsoTexelAlphaV(int ia, int n, T beta, T rp) {
  return gtsoStepUnwarp(T(ia) / T(n - 1), beta, gtsoSigma(rp), gtsoStepT<T>(n));
}
// The physical parameters of texel i (the bake's inverse maps): alphaV is the cone half-angle the
// texel is baked at, possibly outside [0, pi/2] (the continuation texels of gtsoSpanAbove); A is
// that of alphaV clamped to [0, pi/2].
template <class T>
GtsoPhysical<T> gtsoTexelPhysical(int dims, const int* i, const int* size) {
  auto tOf = [&](int d) { return T(i[d]) / T(size[d] - 1); };
  GtsoPhysical<T> p;
  p.rp = gtsoRoughUnwarp(tOf(2));
  p.thetaO = gtsoThetaUnwarp(dims == 3 ? tOf(1) : tOf(3), p.rp);
  p.beta =
      dims == 3 ? p.thetaO : gtsoBetaUnwarp(tOf(1), p.thetaO, p.rp, gtsoBetaSplitT<T>(size[1]));
  p.alphaV = gtsoTexelAlphaV(i[0], size[0], p.beta, p.rp);
  const T halfPi = T(kGtsoPi / 2);
  const T sv = std::sin(p.alphaV < T(0) ? T(0) : (p.alphaV > halfPi ? halfPi : p.alphaV));
  p.A = sv * sv;
  return p;
}

// ---- texels ----

enum class GtsoTexelFormat { kFloat32, kBc4, kR16, kR8 };

// A volume texture as stored in gtso3d/gtso4d files: width x height x depth texels, x fastest;
// BC4: 4x4 blocks over (x, y), blocks in memory order (slices, rows of blocks, left to right).
struct GtsoVolume {
  GtsoTexelFormat format;
  const void* texels;
  int width, height, depth;
};

// Which table axis each texture axis holds: texture x, y, z = table axes axis[0], axis[1],
// axis[2] of (0 = A, 1 = theta_o (3D) / beta (4D), 2 = r_p). `gtbake encode` chooses it per table
// (the BC4 block plane is texture (x, y)). The 4D theta_o axis w is tiled (docs/export.md §2c):
// slice w is the N_x x N_y x N_z tile at texel (N_x (w mod tilesX), 0, N_z floor(w / tilesX)),
// tilesX slices across x and the rest down z. tilesX = 1 is the fold (texture z' = w N_z + z,
// depth N_z N_w); the atlas tiles across x so that no extent exceeds 256 texels. 3D: tilesX = 1.
struct GtsoLayout {
  int axis[3];
  int tilesX = 1;
};
inline constexpr GtsoLayout kGtsoIdentityLayout = {{0, 1, 2}};

// BC4_UNORM decode of texel (4*row + col) of one block as a little-endian uint64, D3D float
// arithmetic (the definition of the format gtbake encodes against).
constexpr float gtsoBc4DecodeTexel(std::uint64_t block, int texel) {
  const int r0 = static_cast<int>(block & 0xFF);
  const int r1 = static_cast<int>((block >> 8) & 0xFF);
  const int code = static_cast<int>((block >> (16 + 3 * texel)) & 7);
  const float e0 = static_cast<float>(r0) / 255.0f;
  const float e1 = static_cast<float>(r1) / 255.0f;
  if (code == 0) return e0;
  if (code == 1) return e1;
  if (r0 > r1) {
    return (static_cast<float>(8 - code) * e0 + static_cast<float>(code - 1) * e1) / 7.0f;
  }
  if (code == 6) return 0.0f;
  if (code == 7) return 1.0f;
  return (static_cast<float>(6 - code) * e0 + static_cast<float>(code - 1) * e1) / 5.0f;
}

inline float gtsoFetchTexel(const GtsoVolume& v, int x, int y, int z) {
  const std::size_t linear = (static_cast<std::size_t>(z) * v.height + y) * v.width + x;
  switch (v.format) {
    case GtsoTexelFormat::kFloat32:
      return static_cast<const float*>(v.texels)[linear];
    case GtsoTexelFormat::kR16:
      return static_cast<float>(static_cast<const std::uint16_t*>(v.texels)[linear]) / 65535.0f;
    case GtsoTexelFormat::kR8:
      return static_cast<float>(static_cast<const std::uint8_t*>(v.texels)[linear]) / 255.0f;
    case GtsoTexelFormat::kBc4:
      break;
  }
  const std::size_t block =
      (static_cast<std::size_t>(z) * (v.height / 4) + y / 4) * (v.width / 4) + x / 4;
  return gtsoBc4DecodeTexel(static_cast<const std::uint64_t*>(v.texels)[block],
                            (y % 4) * 4 + x % 4);
}

// Half-texel remap: t = 0 and t = 1 land on the centres of the first and last texels.
constexpr float gtsoTexelRemap(float t, int n) {
  return (t * static_cast<float>(n - 1) + 0.5f) / static_cast<float>(n);
}

// Trilinear filter at texel-space position p[3] (texel centres on integers) inside the box of
// n[3] texels whose first texel is lo[3], with clamp-to-edge addressing at the box's faces: it
// reads texels of the box only (a 4D tile, or the whole volume).
inline float gtsoSampleTexels(const GtsoVolume& v, const float* p, const int* lo, const int* n) {
  int i0[3] = {0, 0, 0}, i1[3] = {0, 0, 0};
  float fr[3] = {0.0f, 0.0f, 0.0f};
  for (int a = 0; a < 3; ++a) {
    const float fl = std::floor(p[a]);
    fr[a] = p[a] - fl;
    const int i = static_cast<int>(fl);
    i0[a] = lo[a] + (i < 0 ? 0 : (i > n[a] - 1 ? n[a] - 1 : i));
    i1[a] = lo[a] + (i + 1 < 0 ? 0 : (i + 1 > n[a] - 1 ? n[a] - 1 : i + 1));
  }
  float result = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    const float w = (corner & 1 ? fr[0] : 1.0f - fr[0]) * (corner & 2 ? fr[1] : 1.0f - fr[1]) *
                    (corner & 4 ? fr[2] : 1.0f - fr[2]);
    result += w * gtsoFetchTexel(v, corner & 1 ? i1[0] : i0[0], corner & 2 ? i1[1] : i0[1],
                                 corner & 4 ? i1[2] : i0[2]);
  }
  return result;
}

// Trilinear filter with clamp-to-edge addressing at normalised coordinates, as a GPU samples a
// volume (weights in float; hardware quantises them to >= 8 fractional bits).
inline float gtsoSampleTrilinear(const GtsoVolume& v, float cu, float cv, float cw) {
  const int lo[3] = {0, 0, 0}, n[3] = {v.width, v.height, v.depth};
  const float p[3] = {cu * static_cast<float>(n[0]) - 0.5f, cv * static_cast<float>(n[1]) - 0.5f,
                      cw * static_cast<float>(n[2]) - 0.5f};
  return gtsoSampleTexels(v, p, lo, n);
}

// S3 from a 3D table of size[3] texels per axis (A, theta_o, r_p), stored in `layout`
// (texture extent along x = size[layout.axis[0]], etc.). gtso3DLookupAt filters at the axis
// coordinates gtso3DAxes returns, for a caller that reads several tables at the same point.
inline float gtso3DLookupAt(const GtsoVolume& table, const int* size, const GtsoAxisT<float>& a,
                            const GtsoLayout& layout = kGtsoIdentityLayout) {
  float c[3];
  for (int k = 0; k < 3; ++k) c[k] = gtsoTexelRemap(a.t[k], size[k]);
  return gtsoSampleTrilinear(table, c[layout.axis[0]], c[layout.axis[1]], c[layout.axis[2]]);
}
inline float gtso3DLookup(const GtsoVolume& table, const int* size, float A, float cosBeta,
                          float rp, const GtsoLayout& layout = kGtsoIdentityLayout) {
  return gtso3DLookupAt(table, size, gtso3DAxes(A, cosBeta, rp, size), layout);
}

// The first texel of theta_o slice w's tile in a 4D volume whose tiles are n[3] texels
// (GtsoLayout::tilesX).
inline void gtso4DTileOrigin(const GtsoLayout& layout, const int* n, int w, int* lo) {
  lo[0] = n[0] * (w % layout.tilesX);
  lo[1] = 0;
  lo[2] = n[2] * (w / layout.tilesX);
}

// S4 from a 4D table of size[4] texels per axis (A, beta, r_p, theta_o): the axes of `layout` on
// texture x, y, z, theta_o tiled (GtsoLayout): two trilinear fetches in the tiles of the
// neighbouring theta_o slices and a lerp. Each fetch filters at the half-texel-remapped position
// t (N - 1) inside its tile and addresses only the tile's texels (clamp to the tile's edge
// texels), so the result does not depend on tilesX: the fold and the atlas of the same texels
// agree to the last bit (docs/export.md §2c). gtso4DLookupAt filters at the axis coordinates
// gtso4DAxes returns.
inline float gtso4DLookupAt(const GtsoVolume& table, const int* size, const GtsoAxisT<float>& a,
                            const GtsoLayout& layout = kGtsoIdentityLayout) {
  const float sw = a.t[3] * static_cast<float>(size[3] - 1);
  int s0 = static_cast<int>(sw);
  if (s0 > size[3] - 2) s0 = size[3] - 2;
  int n[3];
  float p[3];
  for (int k = 0; k < 3; ++k) {
    n[k] = size[layout.axis[k]];
    p[k] = a.t[layout.axis[k]] * static_cast<float>(n[k] - 1);
  }
  int lo0[3], lo1[3];
  gtso4DTileOrigin(layout, n, s0, lo0);
  gtso4DTileOrigin(layout, n, s0 + 1, lo1);
  const float f0 = gtsoSampleTexels(table, p, lo0, n);
  const float f1 = gtsoSampleTexels(table, p, lo1, n);
  return f0 + (f1 - f0) * (sw - static_cast<float>(s0));
}
inline float gtso4DLookup(const GtsoVolume& table, const int* size, float A, float cosBeta,
                          float rp, float cosThetaO,
                          const GtsoLayout& layout = kGtsoIdentityLayout) {
  return gtso4DLookupAt(table, size, gtso4DAxes(A, cosBeta, rp, cosThetaO, size), layout);
}

// ---- closed forms ----

// Multi-bounce G(A, rho) = a A^3 - b A^2 + c A (paper Eq. 10) with a = ka[0] rho + ka[1] etc.
// ({slope, intercept}); unclamped (a shipped profile is monotone with G(1) = 1,
// docs/profiles.md §9).
inline float gtsoMultiBounce(const float* ka, const float* kb, const float* kc, float A,
                             float albedo) {
  const float a = ka[0] * albedo + ka[1];
  const float b = kb[0] * albedo + kb[1];
  const float c = kc[0] * albedo + kc[1];
  return ((a * A - b) * A + c) * A;
}

// Multi-bounce G(A, rho) from a profile's monotone table (docs/profiles.md §8): G at `nodes`
// values of A (0, 1/(nodes - 1), ..., 1) for each of `rows` albedos rho[] (ascending), row-major
// values[row * nodes + node]; linear in A between nodes (A clamped to [0, 1]) and in the albedo
// between rows (clamped to the rows). nodes >= 2, rows >= 1. The one definition: `gtbake fit`
// scores its tables with it (double) and the header's multiBounce(table, A, albedo) calls it.
template <class T>
T gtsoMultiBounceTableRow(const T* values, int nodes, int row, T A) {
  const T x = (A < T(0) ? T(0) : A > T(1) ? T(1) : A) * T(nodes - 1);
  const int i = int(x) < nodes - 2 ? int(x) : nodes - 2;
  const T* v = values + row * nodes;
  return v[i] + (x - T(i)) * (v[i + 1] - v[i]);
}
template <class T>
T gtsoMultiBounceTable(const T* rho, const T* values, int rows, int nodes, T A, T albedo) {
  int j0 = 0, j1 = 0;
  T s = T(0);
  if (albedo >= rho[rows - 1]) {
    j0 = j1 = rows - 1;
  } else if (albedo > rho[0]) {
    for (int j = 0; j < rows - 1; ++j) j0 = rho[j] < albedo ? j : j0;
    j1 = j0 + 1;
    s = (albedo - rho[j0]) / (rho[j1] - rho[j0]);
  }
  const T g0 = gtsoMultiBounceTableRow(values, nodes, j0, A);
  return g0 + s * (gtsoMultiBounceTableRow(values, nodes, j1, A) - g0);
}

// Solid angle of the intersection of two spherical caps of half-angles alphaV, alphaS whose axes
// are beta apart (radians; exact for half-angles up to pi/2; Mazonka 2012 Eq. 12).
inline float gtsoCapIntersection(float alphaV, float alphaS, float beta) {
  const float pi = static_cast<float>(kGtsoPi);
  if (beta >= alphaV + alphaS) return 0.0f;
  if (beta <= std::fabs(alphaV - alphaS)) {
    const float h = std::sin(0.5f * (alphaV < alphaS ? alphaV : alphaS));
    return 4.0f * pi * h * h;  // 2 pi (1 - cos), without the cancellation
  }
  const float c1 = std::cos(alphaV), c2 = std::cos(alphaS), cd = std::cos(beta);
  const float s1 = std::sin(alphaV), s2 = std::sin(alphaS), sd = std::sin(beta);
  const float t0 = gtsoAcos((cd - c1 * c2) / (s1 * s2));
  const float t1 = gtsoAcos((c2 - cd * c1) / (sd * s1));
  const float t2 = gtsoAcos((c1 - cd * c2) / (sd * s2));
  const float omega = 2.0f * (pi - t0 - c1 * t1 - c2 * t2);
  return omega > 0.0f ? omega : 0.0f;
}

// 1 - exp(x) for x <= 0 without cancellation near 0 (the shaders have no expm1).
inline float gtsoOneMinusExp(float x) {
  return std::fabs(x) < 1e-3f ? -x * (1.0f + 0.5f * x) : 1.0f - std::exp(x);
}

// Cone-to-cone specular occlusion (paper Eq. 19): visibility cone cos(alpha_v) = sqrt(1 - A),
// specular cone cos(alpha_s) = u^(alpha^2/2), alpha = rp^2, axes beta apart; S = cap
// intersection / (2 pi (1 - cos(alpha_s))), with 1 - cos(alpha_s) kept precise for tiny lobes.
inline float gtsoConeModel(float u, float A, float cosBeta, float rp) {
  const float alpha = rp * rp;
  const float oneMinusCosS = gtsoOneMinusExp(0.5f * alpha * alpha * std::log(u));
  const float alphaV = gtsoAlphaV(A);
  const float beta = gtsoAcos(cosBeta);
  if (oneMinusCosS <= 0.0f) return beta <= alphaV && A > 0.0f ? 1.0f : 0.0f;  // mirror limit
  const float alphaS = 2.0f * std::asin(std::sqrt(0.5f * oneMinusCosS));
  return gtsoClamp01(gtsoCapIntersection(alphaV, alphaS, beta) /
                     (2.0f * static_cast<float>(kGtsoPi) * oneMinusCosS));
}

// ---- closed-form S3 (no sampler): a two-component log-logistic step in the odds of A ----
//
// S3(A, theta_o, rp) is the share of the lobe's weighted directions wi with polar angle
// theta_i <= alpha_v: a CDF in alpha_v, 0 at A = 0 and 1 at A = 1. In the log-odds
// u = log tan(alpha_v) = log(A / (1 - A)) / 2 (-inf at A = 0, +inf at A = 1) it is close to a
// logistic step (a sharp core) plus a broad component for GGX's long tails:
//   S = (1 - w) L(z) + w L(p_t d),  L(z) = 1 / (1 + exp(-z)),  d = u - u_m,
//   z = p_lo d (d < 0), p_hi d (d >= 0),
//   exp(2 u_m) = tan^2 theta_m = (tan^2 theta_o + a) / (1 + b tan^2 theta_o) exp(2 alpha P_c),
//     a = alpha^2 exp(P_a), b = alpha^2 exp(P_b): the median stays inside (0, pi/2) for a lobe
//     centred on n (theta_o = 0) and for one clipped by the horizon (theta_o = pi/2),
//   p_lo = hypot(exp(P_0lo), h exp(-P_wlo)), p_hi likewise, h = sin(2 theta_o) / (2 alpha): a lobe
//     of angular width ~alpha at theta_o has slope ~h in u; exp(P_0) is the slope of a lobe
//     centred on n (GGX there: S ~ tan^2(alpha_v/2) / (tan^2(alpha_v/2) + alpha^2), slope 2),
//   w = L(P_w), p_t = exp(P_t),
// with alpha = rp^2 + kGtsoS3ClosedFormAlphaFloor and each P a polynomial in the basis of
// gtsoS3ClosedFormBasis: m = sqrt(cos theta_o), rp and q = h / (1 + h) (how far the lobe sits from
// the pole and the horizon, in lobe widths). Coefficient set s (P_a, P_b, P_c, P_0lo, P_wlo, P_0hi,
// P_whi, P_w, P_t) is k[s * kGtsoS3ClosedFormBasis + i]. S = 0 at A = 0 and 1 at A = 1 exactly and
// is monotone in A. `gtbake gtso` fits k by least squares against the integrator
// (src/gtso/s3_closed_form.h; docs/gtso.md "A closed form for engines short of samplers").
// Templated on the coefficient type C (float at runtime; double or a Ceres Jet in the fit) and the
// input type T. ALU (kGtsoS3ClosedFormAlu): 10 exp, 2 log, 4 sqrt, 7 div, ~120 mul/add (90 of
// them the nine polynomials, which depend on cos theta_o and rp only).
inline constexpr int kGtsoS3ClosedFormBasis = 10;
inline constexpr int kGtsoS3ClosedFormSets = 9;
inline constexpr int kGtsoS3ClosedFormCoeffs = kGtsoS3ClosedFormSets * kGtsoS3ClosedFormBasis;
inline constexpr double kGtsoS3ClosedFormAlphaFloor = 1e-4;  // lobe width at rp = 0 (radians)
inline constexpr const char* kGtsoS3ClosedFormAlu = "10 exp, 2 log, 4 sqrt, 7 div, ~120 mul/add";

// The polynomial terms: 1, m, rp, m rp, m^2, rp^2, q, q m, q rp, q^2.
template <class T>
void gtsoS3ClosedFormBasis(T m, T rp, T q, T* b) {
  b[0] = T(1);
  b[1] = m;
  b[2] = rp;
  b[3] = m * rp;
  b[4] = m * m;
  b[5] = rp * rp;
  b[6] = q;
  b[7] = q * m;
  b[8] = q * rp;
  b[9] = q * q;
}

// 1 / (1 + exp(-z)) without overflow in either direction.
template <class C>
C gtsoLogistic(C z) {
  using std::exp;
  if (z < C(0)) {
    const C e = exp(z);
    return e / (C(1) + e);
  }
  return C(1) / (C(1) + exp(-z));
}

// The parameters of one lobe (cos theta_o, rp): median u_m, core slopes, tail weight and slope.
template <class C>
struct GtsoS3ClosedFormLobe {
  C median, slopeLo, slopeHi, tailWeight, tailSlope;
};

template <class C, class T>
GtsoS3ClosedFormLobe<C> gtsoS3ClosedFormLobe(const C* k, T cosThetaO, T rp) {
  using std::exp;
  using std::log;
  using std::sqrt;
  const T mu = gtsoClamp01(cosThetaO);
  const T r = gtsoClamp01(rp);
  const T alpha = r * r + T(kGtsoS3ClosedFormAlphaFloor);
  const T mu2 = mu * mu, sin2 = T(1) - mu * mu;
  const T h = mu * std::sqrt(sin2) / alpha;  // sin(2 theta_o) / (2 alpha)
  T b[kGtsoS3ClosedFormBasis];
  gtsoS3ClosedFormBasis(std::sqrt(mu), r, h / (T(1) + h), b);
  C p[kGtsoS3ClosedFormSets];
  for (int s = 0; s < kGtsoS3ClosedFormSets; ++s) {
    const C* ks = k + s * kGtsoS3ClosedFormBasis;
    C sum = ks[0] * b[0];
    for (int i = 1; i < kGtsoS3ClosedFormBasis; ++i) sum = sum + ks[i] * b[i];
    p[s] = sum;
  }
  const C a = alpha * alpha * exp(p[0]);
  const C bb = alpha * alpha * exp(p[1]);
  // tan^2 theta_o = sin2 / mu2, multiplied through by mu2 (finite at grazing, mu = 0).
  const C median = T(0.5) * log((sin2 + a * mu2) / (mu2 + bb * sin2)) + alpha * p[2];
  const C lo0 = exp(p[3]), lo1 = h * exp(-p[4]);
  const C hi0 = exp(p[5]), hi1 = h * exp(-p[6]);
  return {median, sqrt(lo0 * lo0 + lo1 * lo1), sqrt(hi0 * hi0 + hi1 * hi1), gtsoLogistic(p[7]),
          exp(p[8])};
}

// S from the lobe parameters at A (exactly 0 and 1 at the ends).
template <class C, class T>
C gtsoS3ClosedFormFromLobe(const GtsoS3ClosedFormLobe<C>& lobe, T A) {
  if (!(A > T(0))) return C(0);
  if (!(A < T(1))) return C(1);
  const T u = T(0.5) * std::log(A / (T(1) - A));
  const C d = u - lobe.median;
  const C z = d < C(0) ? d * lobe.slopeLo : d * lobe.slopeHi;
  return (C(1) - lobe.tailWeight) * gtsoLogistic(z) +
         lobe.tailWeight * gtsoLogistic(d * lobe.tailSlope);
}

// S3(A, cosBeta, rp) from the kGtsoS3ClosedFormCoeffs coefficients k; cosBeta = cos theta_o = n.wr
// (the bent normal taken as n, like gtso3DLookup), rp perceptual roughness (alpha = rp^2).
template <class C, class T>
C gtsoS3ClosedForm(const C* k, T A, T cosBeta, T rp) {
  return gtsoS3ClosedFormFromLobe(gtsoS3ClosedFormLobe(k, cosBeta, rp), A);
}

}  // namespace gtbake

#endif  // GTBAKE_GTSO_LOOKUP_H
