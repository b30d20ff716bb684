// Philox4x32-10 (Salmon et al., SC'11) over arrays of counters: the words CounterRng::words gives,
// for many walks at once: eight counters per step with AVX2 where the CPU has it, else a plain
// loop the compiler vectorizes for SSE2. Integer arithmetic, so every path gives the same words.
// The walks of one point draw their bounce directions here (escape_walk.h); tests/sweep checks
// every word against CounterRng.
#pragma once

#include <cstdint>

namespace gtbake {

class PhiloxLanes {
 public:
  // The key of CounterRng(seed, stream): the same words for the same (seed, stream, index, block).
  PhiloxLanes(std::uint64_t seed, std::uint64_t stream);

  // For i < count: the four words of CounterRng(seed, stream).words(index[i], block), written to
  // w0[i], w1[i], w2[i], w3[i]. Indices are below 2^31 (walk numbers), so counter word 1 is 0.
  void words(const std::int32_t* index, int count, std::uint32_t block, std::uint32_t* w0,
             std::uint32_t* w1, std::uint32_t* w2, std::uint32_t* w3) const;

 private:
  std::uint32_t key0_;
  std::uint32_t key1_;
  std::uint32_t stream_hi_;  // counter word 3, as in CounterRng
  bool avx2_;                // this CPU runs the 8-lane AVX2 rounds
};

// A uniform float in [0, 1) from a word: its top 24 bits times 2^-24, as CounterRng::uniform4.
inline float wordToUniform(std::uint32_t w) {
  constexpr float kScale = 1.0f / 16777216.0f;  // 2^-24: 24 bits fill a float's significand
  // Through int32 (the value is below 2^24): exact, and a plain SIMD conversion.
  return static_cast<float>(static_cast<std::int32_t>(w >> 8)) * kScale;
}

}  // namespace gtbake
