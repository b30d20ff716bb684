// Texture layouts (encode/bc4_layout.h, runtime/gtso_runtime.h GtsoLayout): the runtime lookup of
// a permuted volume equals the table-order lookup at random inputs within float rounding, for
// every layout of both tables and every texel format; and swapping texture x and y (which the 4D
// candidates omit) leaves the exact BC4 encoding's decoded texels unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "encode/bc4_layout.h"
#include "runtime/gtso_runtime.h"
#include "texture/bc4_encoder.h"
#include "texture/texture_containers.h"

namespace gtbake {
namespace {

// A smooth table with a step along A, like S, on dims (x fastest; 4D folded).
GtsoTable smoothTable(const std::vector<int>& dims) {
  GtsoTable t;
  t.file = dims.size() == 3 ? "gtso3d.f32" : "gtso4d.f32";
  t.dims = dims;
  const int w = dims.size() == 4 ? dims[3] : 1;
  t.volume = {dims[0], dims[1], dims[2] * w};
  for (int l = 0; l < w; ++l)
    for (int z = 0; z < dims[2]; ++z)
      for (int y = 0; y < dims[1]; ++y)
        for (int x = 0; x < dims[0]; ++x) {
          const double a = x / (dims[0] - 1.0), b = y / (dims[1] - 1.0), r = z / (dims[2] - 1.0);
          t.values.push_back(
              static_cast<float>(0.5 + 0.45 * std::tanh((a - 0.3 - 0.4 * b) / (0.05 + 0.3 * r)) *
                                           (1.0 - 0.2 * l / w)));
        }
  return t;
}

std::vector<GtsoLayout> allLayouts() {
  return {{{0, 1, 2}}, {{1, 0, 2}}, {{0, 2, 1}}, {{2, 0, 1}}, {{1, 2, 0}}, {{2, 1, 0}}};
}

TEST(Bc4Layout, PermutedLookupEqualsTableOrderLookup) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f), u11(-1.0f, 1.0f);
  for (const std::vector<int>& dims :
       {std::vector<int>{8, 12, 16}, std::vector<int>{8, 12, 16, 4}}) {
    const GtsoTable t = smoothTable(dims);
    const bool four = dims.size() == 4;
    const GtsoVolume identity{GtsoTexelFormat::kFloat32, t.values.data(), t.volume[0], t.volume[1],
                              t.volume[2]};
    for (const GtsoLayout& l : allLayouts()) {
      const std::vector<float> p = permuteToLayout(t, l);
      const std::array<int, 3> v = layoutVolume(t, l);
      const auto r16 = quantizeUnorm(p.data(), p.size(), TexelFormat::kR16);
      std::vector<std::uint16_t> r16t(p.size());
      for (std::size_t i = 0; i < p.size(); ++i)
        r16t[i] = static_cast<std::uint16_t>(r16[2 * i] | r16[2 * i + 1] << 8);
      const auto q = quantizeUnorm(t.values.data(), t.values.size(), TexelFormat::kR16);
      std::vector<std::uint16_t> qt(t.values.size());
      for (std::size_t i = 0; i < qt.size(); ++i)
        qt[i] = static_cast<std::uint16_t>(q[2 * i] | q[2 * i + 1] << 8);
      const GtsoVolume permuted{GtsoTexelFormat::kFloat32, p.data(), v[0], v[1], v[2]};
      const GtsoVolume permuted16{GtsoTexelFormat::kR16, r16t.data(), v[0], v[1], v[2]};
      const GtsoVolume identity16{GtsoTexelFormat::kR16, qt.data(), t.volume[0], t.volume[1],
                                  t.volume[2]};
      float worst = 0.0f, worst16 = 0.0f;
      for (int k = 0; k < 3000; ++k) {
        const float A = u01(rng), cb = u11(rng), rp = u01(rng), co = u01(rng);
        const float a = four ? gtso4DLookup(permuted, dims.data(), A, cb, rp, co, l)
                             : gtso3DLookup(permuted, dims.data(), A, cb, rp, l);
        const float b = four ? gtso4DLookup(identity, dims.data(), A, cb, rp, co)
                             : gtso3DLookup(identity, dims.data(), A, cb, rp);
        const float a16 = four ? gtso4DLookup(permuted16, dims.data(), A, cb, rp, co, l)
                               : gtso3DLookup(permuted16, dims.data(), A, cb, rp, l);
        const float b16 = four ? gtso4DLookup(identity16, dims.data(), A, cb, rp, co)
                               : gtso3DLookup(identity16, dims.data(), A, cb, rp);
        worst = std::max(worst, std::fabs(a - b));
        worst16 = std::max(worst16, std::fabs(a16 - b16));
      }
      // Eight weights of products of three fractions and a sum of eight terms in another order:
      // a few float ulps of values in [0, 1].
      EXPECT_LE(worst, 4e-7f) << dims.size() << "D layout " << layoutSwizzle(l);
      EXPECT_LE(worst16, 4e-7f) << dims.size() << "D layout " << layoutSwizzle(l);
    }
  }
}

// The identity layout is the table order; a wrong assignment is caught (the test above is not
// vacuous): reading a permuted volume as if it were in table order differs.
TEST(Bc4Layout, IdentityIsTableOrderAndAWrongLayoutDiffers) {
  const GtsoTable t = smoothTable({8, 8, 8});
  EXPECT_EQ(permuteToLayout(t, kGtsoIdentityLayout), t.values);
  const GtsoLayout l{{1, 2, 0}};
  const std::vector<float> p = permuteToLayout(t, l);
  const GtsoVolume permuted{GtsoTexelFormat::kFloat32, p.data(), 8, 8, 8};
  const GtsoVolume identity{GtsoTexelFormat::kFloat32, t.values.data(), 8, 8, 8};
  const int dims[3] = {8, 8, 8};
  float worst = 0.0f;
  for (float A = 0.05f; A < 1.0f; A += 0.1f) {
    worst = std::max(worst, std::fabs(gtso3DLookup(permuted, dims, A, 0.6f, 0.4f) -
                                      gtso3DLookup(identity, dims, A, 0.6f, 0.4f)));
  }
  EXPECT_GT(worst, 0.05f);
  EXPECT_EQ(layoutSwizzle(l), "yzx");
}

// x <-> y swaps hold the same 16 texels per block: the decoded texels agree (the reason the 4D
// candidates list only x-before-y block planes).
TEST(Bc4Layout, SwappingTheBlockPlaneAxesKeepsTheDecodedTexels) {
  const GtsoTable t = smoothTable({16, 16, 8});
  const Bc4Encoder encoder;
  for (const auto& [a, b] : {std::pair{GtsoLayout{{0, 1, 2}}, GtsoLayout{{1, 0, 2}}},
                             std::pair{GtsoLayout{{0, 2, 1}}, GtsoLayout{{2, 0, 1}}}}) {
    const std::vector<float> pa = permuteToLayout(t, a), pb = permuteToLayout(t, b);
    const std::array<int, 3> va = layoutVolume(t, a), vb = layoutVolume(t, b);
    const Bc4Volume ea = encodeBc4Volume(encoder, pa.data(), va[0], va[1], va[2], nullptr);
    const Bc4Volume eb = encodeBc4Volume(encoder, pb.data(), vb[0], vb[1], vb[2], nullptr);
    const std::vector<float> da = decodeBc4Volume(ea.bytes.data(), va[0], va[1], va[2]);
    const std::vector<float> db = decodeBc4Volume(eb.bytes.data(), vb[0], vb[1], vb[2]);
    // texel (x, y, z) of layout a is texel (y, x, z) of layout b
    int differing = 0;
    for (int z = 0; z < va[2]; ++z)
      for (int y = 0; y < va[1]; ++y)
        for (int x = 0; x < va[0]; ++x) {
          differing += da[(static_cast<std::size_t>(z) * va[1] + y) * va[0] + x] !=
                       db[(static_cast<std::size_t>(z) * vb[1] + x) * vb[0] + y];
        }
    EXPECT_EQ(differing, 0) << layoutSwizzle(a);
    EXPECT_EQ(ea.rmse, eb.rmse);
  }
}

}  // namespace
}  // namespace gtbake
