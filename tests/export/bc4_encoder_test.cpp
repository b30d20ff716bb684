// BC4: the layout against hand-packed bytes, the decode against the spec's formulas, and the
// encoder's optimum against exhaustive search over all 65,536 endpoint pairs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "common/error.h"
#include "texture/bc4_block.h"
#include "texture/bc4_encoder.h"

namespace gtbake {
namespace {

// The D3D11.3 BC4_UNORM palette written out longhand, independent of bc4Palette's loops.
std::array<float, 8> specPalette(int r0, int r1) {
  const float e0 = r0 / 255.0f;
  const float e1 = r1 / 255.0f;
  if (r0 > r1) {
    return {e0,
            e1,
            (6 * e0 + 1 * e1) / 7.0f,
            (5 * e0 + 2 * e1) / 7.0f,
            (4 * e0 + 3 * e1) / 7.0f,
            (3 * e0 + 4 * e1) / 7.0f,
            (2 * e0 + 5 * e1) / 7.0f,
            (1 * e0 + 6 * e1) / 7.0f};
  }
  return {e0,
          e1,
          (4 * e0 + 1 * e1) / 5.0f,
          (3 * e0 + 2 * e1) / 5.0f,
          (2 * e0 + 3 * e1) / 5.0f,
          (1 * e0 + 4 * e1) / 5.0f,
          0.0f,
          1.0f};
}

struct Exhaustive {
  int key = -1;
  double error = std::numeric_limits<double>::infinity();
};

// Every (red_0, red_1), every texel at its nearest entry, row-major double sum, lowest key on ties.
Exhaustive exhaustiveSearch(const std::array<float, 16>& block) {
  Exhaustive best;
  double v[16];
  for (int t = 0; t < 16; ++t) v[t] = std::fmin(std::fmax(double(block[t]), 0.0), 1.0);
  for (int key = 0; key < 65536; ++key) {
    const std::array<float, 8> p = specPalette(key >> 8, key & 255);
    double sum = 0.0;
    for (int t = 0; t < 16 && sum <= best.error; ++t) {
      double nearest = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 8; ++k) nearest = std::fmin(nearest, (p[k] - v[t]) * (p[k] - v[t]));
      sum += nearest;
    }
    if (sum < best.error) best = {key, sum};
  }
  return best;
}

double decodedError(const Bc4Block& block, const std::array<float, 16>& target) {
  const std::array<float, 16> d = decodeBc4Block(block.data());
  double sum = 0.0;
  for (int t = 0; t < 16; ++t) {
    const double x = std::fmin(std::fmax(double(target[t]), 0.0), 1.0);
    sum += (d[t] - x) * (d[t] - x);
  }
  return sum;
}

TEST(Bc4Block, PaletteMatchesSpecFormulas) {
  for (int key = 0; key < 65536; ++key) {
    const Bc4Palette a = bc4Palette(key >> 8, key & 255);
    const std::array<float, 8> b = specPalette(key >> 8, key & 255);
    for (int k = 0; k < 8; ++k) ASSERT_EQ(a[k], b[k]) << key << " " << k;
  }
}

TEST(Bc4Block, LayoutTexelZeroInLowestBits) {
  std::array<std::uint8_t, 16> idx{};
  idx[0] = 5;   // bits 0..2
  idx[1] = 3;   // bits 3..5
  idx[15] = 7;  // bits 45..47
  const Bc4Block b = packBc4Block(200, 10, idx);
  EXPECT_EQ(b[0], 200);
  EXPECT_EQ(b[1], 10);
  EXPECT_EQ(b[2], 0x1D);  // 101 | 011 << 3 = 0b011101
  EXPECT_EQ(b[3], 0);
  EXPECT_EQ(b[7], 0xE0);  // 7 << (45 − 40)
  const std::array<float, 16> d = decodeBc4Block(b.data());
  const std::array<float, 8> p = specPalette(200, 10);
  EXPECT_EQ(d[0], p[5]);
  EXPECT_EQ(d[1], p[3]);
  EXPECT_EQ(d[2], p[0]);
  EXPECT_EQ(d[15], p[7]);
}

std::vector<std::array<float, 16>> testBlocks() {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  std::vector<std::array<float, 16>> blocks;
  std::array<float, 16> b{};
  for (int n = 0; n < 120; ++n) {  // uniform random
    for (float& x : b) x = uni(rng);
    blocks.push_back(b);
  }
  for (int n = 0; n < 120; ++n) {  // random values in a narrow window
    const float c = uni(rng);
    const float w = 0.002f + 0.1f * uni(rng);
    for (float& x : b) x = c + w * (uni(rng) - 0.5f);
    blocks.push_back(b);
  }
  for (int n = 0; n < 160; ++n) {  // smooth ramps (planes), some leaving [0, 1]
    const float c = uni(rng), gx = 0.2f * (uni(rng) - 0.5f), gy = 0.2f * (uni(rng) - 0.5f);
    const float scale = n % 4 == 0 ? 6.0f : 1.0f;
    for (int t = 0; t < 16; ++t) b[t] = c + scale * (gx * (t % 4) + gy * (t / 4));
    blocks.push_back(b);
  }
  for (int n = 0; n < 40; ++n) {  // constants, including exact palette values and 0, 1
    const float c = n < 3 ? float(n) * 0.5f : n < 20 ? float(n * 13 % 256) / 255.0f : uni(rng);
    b.fill(c);
    blocks.push_back(b);
  }
  for (int n = 0; n < 120; ++n) {  // 0/1 extremes mixed with interior values, and near-extremes
    for (float& x : b) {
      const float r = uni(rng);
      x = r < 0.3f ? 0.0f : r < 0.6f ? 1.0f : n % 2 ? 1.0f - 0.003f * uni(rng) : uni(rng);
    }
    blocks.push_back(b);
  }
  for (int n = 0; n < 200; ++n) {  // real-table-like: a smooth saturating surface, 4×4 window
    const float x0 = uni(rng), y0 = uni(rng), s = 0.03f + 0.1f * uni(rng);
    for (int t = 0; t < 16; ++t) {
      const float x = x0 + s * (t % 4), y = y0 + s * (t / 4);
      b[t] = std::pow(std::fmin(1.0f, x), 0.5f + 2.0f * y) * (1.0f - 0.2f * y * y);
    }
    blocks.push_back(b);
  }
  for (int n = 0; n < 100; ++n) {  // GTSO at low roughness: a soft step (visibility-cone edge)
    const float edge = 4.0f * uni(rng), width = 0.02f + 0.5f * uni(rng), dir = uni(rng);
    for (int t = 0; t < 16; ++t) {
      const float s = (t % 4) * dir + (t / 4) * (1.0f - dir);
      b[t] = 1.0f / (1.0f + std::exp(-(s - edge) / width));
    }
    blocks.push_back(b);
  }
  return blocks;
}

TEST(Bc4Encoder, MatchesExhaustiveOptimumAndKey) {
  const Bc4Encoder encoder;
  for (const auto& block : testBlocks()) {
    const Bc4Encoding enc = encoder.encodeBlock(block.data());
    const Exhaustive ref = exhaustiveSearch(block);
    ASSERT_EQ(enc.error, ref.error) << "block " << block[0] << " " << block[15];
    EXPECT_EQ(enc.block[0] * 256 + enc.block[1], ref.key);
    EXPECT_EQ(decodedError(enc.block, block), ref.error);
  }
}

TEST(Bc4Encoder, RejectsNan) {
  const Bc4Encoder encoder;
  std::array<float, 16> b{};
  b[7] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(encoder.encodeBlock(b.data()), Error);
}

// The x/y swap of an encoded volume (what the layout choice uses instead of encoding a swapped
// candidate again) is byte for byte the encoder's output on the swapped texels, errors included.
TEST(Bc4Encoder, SwappedVolumeEqualsEncodingTheSwappedTexels) {
  const int w = 8, h = 12, d = 3;  // source w x h x d; swapped h x w x d
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> src(static_cast<std::size_t>(w) * h * d), swapped(src.size());
  for (int z = 0; z < d; ++z) {
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        // smooth ramps plus noise: ties and near-ties between endpoint pairs occur
        const float v = 0.5f * (x / 7.0f) + 0.3f * (y / 11.0f) + 0.2f * unit(rng);
        src[(static_cast<std::size_t>(z) * h + y) * w + x] = v;
        swapped[(static_cast<std::size_t>(z) * w + x) * h + y] = v;
      }
    }
  }
  const Bc4Encoder encoder;
  const Bc4Volume a = encodeBc4Volume(encoder, src.data(), w, h, d, nullptr);
  const Bc4Volume direct = encodeBc4Volume(encoder, swapped.data(), h, w, d, nullptr);
  const Bc4Volume derived = swapBc4VolumeXY(a, swapped.data(), h, w, d);
  EXPECT_EQ(derived.bytes, direct.bytes);
  EXPECT_EQ(derived.rmse, direct.rmse);
  EXPECT_EQ(derived.max_abs, direct.max_abs);
  EXPECT_NE(derived.bytes, a.bytes);  // the blocks did move
}

TEST(Bc4Encoder, VolumeIndependentOfThreadCountAndRoundTrips) {
  const int w = 8, h = 8, d = 3;
  std::vector<float> data(w * h * d);
  for (int i = 0; i < w * h * d; ++i) data[i] = 0.5f + 0.45f * std::sin(0.37f * i);
  const Bc4Encoder encoder;
  const Bc4Volume a = encodeBc4Volume(encoder, data.data(), w, h, d, nullptr);
  ASSERT_EQ(a.bytes.size(), std::size_t(w / 4 * h / 4 * d * 8));
  // Block (bx = 1, by = 0, z = 2) is block 2·4 + 1 and holds texels x 4..7, y 0..3 of slice 2.
  std::array<float, 16> expect{};
  for (int t = 0; t < 16; ++t) expect[t] = data[(2 * h + t / 4) * w + 4 + t % 4];
  Bc4Block blk{};
  std::copy(a.bytes.begin() + 9 * 8, a.bytes.begin() + 10 * 8, blk.begin());
  EXPECT_EQ(blk, encoder.encodeBlock(expect.data()).block);
  const std::vector<float> back = decodeBc4Volume(a.bytes.data(), w, h, d);
  double worst = 0.0;
  for (int i = 0; i < w * h * d; ++i) worst = std::fmax(worst, std::fabs(back[i] - data[i]));
  EXPECT_EQ(worst, a.max_abs);
}

}  // namespace
}  // namespace gtbake
