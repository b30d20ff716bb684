// The cosine-weighted direction of one walk step (docs/sweep.md §1): density pdf(ω) = (n·ω)/π about
// the oriented normal n, from a point (u0, u1) of the unit square. Scalar float kernels, inline so
// the walk loops (escape_walk.cpp) can vectorize them over many walks; the one-ray path uses the
// same functions, so both traversals compute every direction bit for bit alike.
//
// Map. The concentric disk map (Shirley & Chiu 1997), area preserving, so a uniform (u0, u1), or a
// uniform point of any grid cell, stays uniform on the unit disk; then Malley's method lifts the
// disk point (x, y) to (x, y, √(1 − x² − y²)), whose density over the hemisphere is cosθ/π.
#pragma once

// x86-64: an AVX2 clone (8 float lanes) of each loop over walks or samples next to the default
// (SSE2, 4 lanes), chosen once at load time; both compute the same IEEE operations, so the same
// bits. GTBAKE_PORTABLE_KERNELS builds the default path only (tests/portable checks the bits
// agree).
#if defined(__x86_64__) && !defined(GTBAKE_PORTABLE_KERNELS)
#define GTBAKE_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define GTBAKE_AVX2_CLONES
#endif

namespace gtbake {

inline constexpr float kQuarterPi = 0.785398163397448309616f;  // π/4, the concentric map's wedge

// The concentric disk point (dx, dy) of (u0, u1) ∈ [0,1)² (Shirley & Chiu 1997; pbrt-v4's
// SampleUniformDiskConcentric, the same orientation as gtso::sampleUniformDiskConcentric).
inline void concentricDisk(float u0, float u1, float* dx, float* dy) {
  // With s = 2u − 1, the disk point is (r cos φ, r sin φ), φ = π/4·t, |t| ≤ 1, in the wedge pair
  // where |sx| > |sy| (r = sx, t = sy/sx), and (r sin φ, r cos φ) with r = sy, t = sx/sy in the
  // other; signed r covers the opposite wedges. So only sin and cos on [−π/4, π/4] are needed:
  // Taylor polynomials to x⁹ and x¹⁰, whose truncation errors (< 2e-9 and 1e-10) lie below
  // float rounding. Selects, no branches. r = 0 only at the disk centre, where the other
  // coordinate is 0 as well: dividing by 1 there gives t = 0.
  const float sx = 2.0f * u0 - 1.0f;
  const float sy = 2.0f * u1 - 1.0f;
  const bool first = (sx < 0.0f ? -sx : sx) > (sy < 0.0f ? -sy : sy);
  const float r = first ? sx : sy;
  const float q = first ? sy : sx;
  const float x = kQuarterPi * (q / (r != 0.0f ? r : 1.0f));
  const float x2 = x * x;
  const float sin_x =
      x * (1.0f + x2 * (-1.0f / 6 + x2 * (1.0f / 120 + x2 * (-1.0f / 5040 + x2 / 362880))));
  const float cos_x =
      1.0f +
      x2 * (-0.5f + x2 * (1.0f / 24 + x2 * (-1.0f / 720 + x2 * (1.0f / 40320 - x2 / 3628800))));
  *dx = r * (first ? cos_x : sin_x);
  *dy = r * (first ? sin_x : cos_x);
}

// The hemisphere point (dx, dy, dz), dz ≥ 0, of (u0, u1) ∈ [0,1)²: the disk point lifted.
inline void concentricHemisphere(float u0, float u1, float* dx, float* dy, float* dz) {
  concentricDisk(u0, u1, dx, dy);
  const float h = 1.0f - *dx * *dx - *dy * *dy;
  *dz = __builtin_sqrtf(h > 0.0f ? h : 0.0f);
}

// Tangents t, s completing the unit normal n to an orthonormal basis (t, s, n) (Duff et al. 2017,
// "Building an orthonormal basis, revisited").
inline void tangentBasis(float nx, float ny, float nz, float t[3], float s[3]) {
  const float sign = nz >= 0.0f ? 1.0f : -1.0f;
  const float a = -1.0f / (sign + nz);
  const float b = nx * ny * a;
  t[0] = 1.0f + sign * nx * nx * a;
  t[1] = sign * b;
  t[2] = -sign * nx;
  s[0] = b;
  s[1] = sign + ny * ny * a;
  s[2] = -ny;
}

// The direction dx·t + dy·s + dz·n in world space: unit length to float rounding (Embree needs no
// normalisation).
inline void cosineDirection(const float n[3], const float t[3], const float s[3], float u0,
                            float u1, float d[3]) {
  float dx;
  float dy;
  float dz;
  concentricHemisphere(u0, u1, &dx, &dy, &dz);
  for (int c = 0; c < 3; ++c) d[c] = dx * t[c] + dy * s[c] + dz * n[c];
}

}  // namespace gtbake
