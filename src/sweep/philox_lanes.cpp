#include "sweep/philox_lanes.h"

#include "common/rng.h"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace gtbake {

namespace {

// Random123's Philox4x32 constants: the round multipliers and the Weyl key increments.
constexpr std::uint32_t kPhiloxM0 = 0xD2511F53u;
constexpr std::uint32_t kPhiloxM1 = 0xCD9E8D57u;
constexpr std::uint32_t kPhiloxW0 = 0x9E3779B9u;
constexpr std::uint32_t kPhiloxW1 = 0xBB67AE85u;
constexpr int kPhiloxRounds = 10;  // Philox4x32-10, the Random123 default CounterRng uses

// The rounds over the arrays in plain C++ (SSE2 auto-vectorized, and the tail of philoxAvx2).
void philoxKernel(const std::int32_t* __restrict index, int count, std::uint32_t block,
                  std::uint32_t key0, std::uint32_t key1, std::uint32_t stream_hi,
                  std::uint32_t* __restrict w0, std::uint32_t* __restrict w1,
                  std::uint32_t* __restrict w2, std::uint32_t* __restrict w3) {
  for (int i = 0; i < count; ++i) {
    std::uint32_t c0 = static_cast<std::uint32_t>(index[i]);
    std::uint32_t c1 = 0;
    std::uint32_t c2 = block;
    std::uint32_t c3 = stream_hi;
    std::uint32_t k0 = key0;
    std::uint32_t k1 = key1;
#pragma GCC unroll 10
    for (int r = 0; r < kPhiloxRounds; ++r) {
      const std::uint64_t p0 = static_cast<std::uint64_t>(kPhiloxM0) * c0;
      const std::uint64_t p1 = static_cast<std::uint64_t>(kPhiloxM1) * c2;
      c0 = static_cast<std::uint32_t>(p1 >> 32) ^ c1 ^ k0;
      c1 = static_cast<std::uint32_t>(p1);
      c2 = static_cast<std::uint32_t>(p0 >> 32) ^ c3 ^ k1;
      c3 = static_cast<std::uint32_t>(p0);
      k0 += kPhiloxW0;
      k1 += kPhiloxW1;
    }
    w0[i] = c0;
    w1[i] = c1;
    w2[i] = c2;
    w3[i] = c3;
  }
}

#if defined(__x86_64__)
// High and low 32 bits of the eight products m · c (32 × 32 → 64 bits) with AVX2: vpmuludq
// multiplies the even 32-bit lanes; the odd ones are shifted down, multiplied, and blended back.
__attribute__((target("avx2"))) inline void mulHiLo8(__m256i c, __m256i m, __m256i* hi,
                                                     __m256i* lo) {
  const __m256i even = _mm256_mul_epu32(c, m);
  const __m256i odd = _mm256_mul_epu32(_mm256_srli_epi64(c, 32), m);
  *lo = _mm256_blend_epi32(even, _mm256_slli_epi64(odd, 32), 0xAA);
  *hi = _mm256_blend_epi32(_mm256_srli_epi64(even, 32), odd, 0xAA);
}

// The same rounds, eight counters per step in AVX2 registers (the compiler's own vectorization of
// the 32 × 32 → 64-bit products is mostly shuffles); integer arithmetic, so the same words.
__attribute__((target("avx2"))) void philoxAvx2(const std::int32_t* index, int count,
                                                std::uint32_t block, std::uint32_t key0,
                                                std::uint32_t key1, std::uint32_t stream_hi,
                                                std::uint32_t* w0, std::uint32_t* w1,
                                                std::uint32_t* w2, std::uint32_t* w3) {
  const __m256i m0 = _mm256_set1_epi32(static_cast<int>(kPhiloxM0));
  const __m256i m1 = _mm256_set1_epi32(static_cast<int>(kPhiloxM1));
  int i = 0;
  for (; i + 8 <= count; i += 8) {
    __m256i c0 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index + i));
    __m256i c1 = _mm256_setzero_si256();
    __m256i c2 = _mm256_set1_epi32(static_cast<int>(block));
    __m256i c3 = _mm256_set1_epi32(static_cast<int>(stream_hi));
    std::uint32_t k0 = key0;
    std::uint32_t k1 = key1;
    for (int r = 0; r < kPhiloxRounds; ++r) {
      __m256i hi0;
      __m256i lo0;
      __m256i hi1;
      __m256i lo1;
      mulHiLo8(c0, m0, &hi0, &lo0);
      mulHiLo8(c2, m1, &hi1, &lo1);
      c0 = _mm256_xor_si256(_mm256_xor_si256(hi1, c1), _mm256_set1_epi32(static_cast<int>(k0)));
      c1 = lo1;
      c2 = _mm256_xor_si256(_mm256_xor_si256(hi0, c3), _mm256_set1_epi32(static_cast<int>(k1)));
      c3 = lo0;
      k0 += kPhiloxW0;
      k1 += kPhiloxW1;
    }
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(w0 + i), c0);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(w1 + i), c1);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(w2 + i), c2);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(w3 + i), c3);
  }
  philoxKernel(index + i, count - i, block, key0, key1, stream_hi, w0 + i, w1 + i, w2 + i, w3 + i);
}

#endif  // __x86_64__

bool cpuHasAvx2() {
#if defined(__x86_64__) && !defined(GTBAKE_PORTABLE_KERNELS)
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

}  // namespace

PhiloxLanes::PhiloxLanes(std::uint64_t seed, std::uint64_t stream) : avx2_(cpuHasAvx2()) {
  const PhiloxKey key(seed, stream);
  key0_ = key.key0;
  key1_ = key.key1;
  stream_hi_ = key.stream_hi;
}

void PhiloxLanes::words(const std::int32_t* index, int count, std::uint32_t block,
                        std::uint32_t* w0, std::uint32_t* w1, std::uint32_t* w2,
                        std::uint32_t* w3) const {
#if defined(__x86_64__)
  if (avx2_) {
    philoxAvx2(index, count, block, key0_, key1_, stream_hi_, w0, w1, w2, w3);
    return;
  }
#endif
  philoxKernel(index, count, block, key0_, key1_, stream_hi_, w0, w1, w2, w3);
}

}  // namespace gtbake
