// BC4_UNORM block layout and the D3D float decode (D3D11.3 functional spec, "BC4").
//
// Layout: 8 bytes per 4×4 block. Byte 0 = red_0, byte 1 = red_1 (UNORM8 endpoints), bytes 2..7 =
// 48 bits of 3-bit palette indices read as one little-endian integer; texel t = 4·row + col
// (row-major, texel 0 = row 0, col 0) occupies bits [3t, 3t + 3).
//
// Decode (what gtbake treats as the definition of the format, float arithmetic, no contraction):
//   e0 = red_0 / 255.0f, e1 = red_1 / 255.0f
//   red_0 >  red_1: p0 = e0, p1 = e1, p_k = ((8 − k)·e0 + (k − 1)·e1) / 7.0f   for k = 2..7
//   red_0 <= red_1: p0 = e0, p1 = e1, p_k = ((6 − k)·e0 + (k − 1)·e1) / 5.0f   for k = 2..5,
//                   p6 = 0.0f, p7 = 1.0f
// e.g. p2 = (6·e0 + 1·e1) / 7.0f, written in the spec's order: products first, then the sum, then
// the division, each rounded to float.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace gtbake {

inline constexpr int kBc4BlockBytes = 8;    // bytes per BC4 block: 2 endpoints + 48 index bits
inline constexpr int kBc4BlockTexels = 16;  // texels per block: 4×4

using Bc4Palette = std::array<float, 8>;
using Bc4Block = std::array<std::uint8_t, kBc4BlockBytes>;

// The eight palette values of endpoints (red_0, red_1), indexed by the 3-bit code.
Bc4Palette bc4Palette(int red0, int red1);

// Packs endpoints and 16 indices (row-major) into the 8-byte layout above.
Bc4Block packBc4Block(int red0, int red1, const std::array<std::uint8_t, 16>& indices);

// The blocks of a BC4 payload as little-endian 64-bit words (GtsoVolume's BC4 texels).
std::vector<std::uint64_t> bc4BlockWords(const std::vector<std::uint8_t>& bytes);

// Decodes one block into 16 floats, row-major.
std::array<float, 16> decodeBc4Block(const std::uint8_t* block);

}  // namespace gtbake
