// Counter-based random numbers: every random draw in gtbake is a pure function of
// (seed, stream, index, dimension), so results are identical for any thread count or schedule.
//
// Built on Random123's Philox4x32-10 (Salmon et al., SC'11): the key holds the seed and a stream
// id (e.g. the pixel), the counter holds the sample index and the dimension block. One call gives
// four independent 32-bit words.
#pragma once

#include <Random123/philox.h>

#include <array>
#include <cstdint>

namespace gtbake {

// The one derivation of the Philox key and counter word 3 from (seed, stream), shared by
// CounterRng and the walks' array Philox (sweep/philox_lanes.h).
struct PhiloxKey {
  std::uint32_t key0, key1, stream_hi;
  PhiloxKey(std::uint64_t seed, std::uint64_t stream)
      : key0(static_cast<std::uint32_t>(seed ^ (stream << 32) ^ (stream >> 32))),
        key1(static_cast<std::uint32_t>((seed >> 32) ^ stream)),
        stream_hi(static_cast<std::uint32_t>(stream >> 32)) {}
};

class CounterRng {
 public:
  CounterRng(std::uint64_t seed, std::uint64_t stream) {
    const PhiloxKey k(seed, stream);
    key_ = {{k.key0, k.key1}};
    stream_hi_ = k.stream_hi;
  }

  // Four uniform 32-bit words for (index, block). Blocks number groups of four dimensions.
  std::array<std::uint32_t, 4> words(std::uint64_t index, std::uint32_t block) const {
    r123::Philox4x32::ctr_type ctr = {{static_cast<std::uint32_t>(index),
                                       static_cast<std::uint32_t>(index >> 32), block, stream_hi_}};
    const auto out = r123::Philox4x32()(ctr, key_);
    return {out[0], out[1], out[2], out[3]};
  }

  // Four uniform floats in [0, 1): the top 24 bits of each word, so 1.0f is never returned.
  std::array<float, 4> uniform4(std::uint64_t index, std::uint32_t block) const {
    const auto w = words(index, block);
    constexpr float kScale = 1.0f / 16777216.0f;  // 2^-24
    return {static_cast<float>(w[0] >> 8) * kScale, static_cast<float>(w[1] >> 8) * kScale,
            static_cast<float>(w[2] >> 8) * kScale, static_cast<float>(w[3] >> 8) * kScale};
  }

 private:
  r123::Philox4x32::key_type key_;
  std::uint32_t stream_hi_;
};

}  // namespace gtbake
