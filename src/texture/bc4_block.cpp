#include "texture/bc4_block.h"

namespace gtbake {

Bc4Palette bc4Palette(int red0, int red1) {
  const float e0 = static_cast<float>(red0) / 255.0f;
  const float e1 = static_cast<float>(red1) / 255.0f;
  Bc4Palette p{};
  p[0] = e0;
  p[1] = e1;
  if (red0 > red1) {
    for (int k = 2; k < 8; ++k) {
      p[k] = (static_cast<float>(8 - k) * e0 + static_cast<float>(k - 1) * e1) / 7.0f;
    }
  } else {
    for (int k = 2; k < 6; ++k) {
      p[k] = (static_cast<float>(6 - k) * e0 + static_cast<float>(k - 1) * e1) / 5.0f;
    }
    p[6] = 0.0f;
    p[7] = 1.0f;
  }
  return p;
}

Bc4Block packBc4Block(int red0, int red1, const std::array<std::uint8_t, 16>& indices) {
  std::uint64_t bits = 0;
  for (int t = 0; t < kBc4BlockTexels; ++t) {
    bits |= static_cast<std::uint64_t>(indices[t] & 7u) << (3 * t);
  }
  Bc4Block block{};
  block[0] = static_cast<std::uint8_t>(red0);
  block[1] = static_cast<std::uint8_t>(red1);
  for (int i = 0; i < 6; ++i) block[2 + i] = static_cast<std::uint8_t>(bits >> (8 * i));
  return block;
}

std::vector<std::uint64_t> bc4BlockWords(const std::vector<std::uint8_t>& bytes) {
  std::vector<std::uint64_t> words(bytes.size() / kBc4BlockBytes, 0);
  for (std::size_t b = 0; b < words.size(); ++b) {
    for (int i = 0; i < kBc4BlockBytes; ++i) {
      words[b] |= static_cast<std::uint64_t>(bytes[kBc4BlockBytes * b + i]) << (8 * i);
    }
  }
  return words;
}

std::array<float, 16> decodeBc4Block(const std::uint8_t* block) {
  const Bc4Palette p = bc4Palette(block[0], block[1]);
  std::uint64_t bits = 0;
  for (int i = 0; i < 6; ++i) bits |= static_cast<std::uint64_t>(block[2 + i]) << (8 * i);
  std::array<float, 16> texels{};
  for (int t = 0; t < kBc4BlockTexels; ++t) texels[t] = p[(bits >> (3 * t)) & 7u];
  return texels;
}

}  // namespace gtbake
