// The 4D table's theta_o tiles (docs/export.md §2c; encode/bc4_layout.h tilesAcrossX, tiledTexel,
// packLayoutChoice; runtime/gtso_runtime.h gtso4DLookup): the atlas shape rule and its limits,
// the texel map round trip, the BC4 blocks of the atlas being the fold's blocks reordered (and
// the encoder's own output on the atlas texels), lookups through the atlas and the fold agreeing
// to the last bit, and the filter never reading another tile.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "common/error.h"
#include "encode/bc4_layout.h"
#include "runtime/gtso_runtime.h"
#include "texture/bc4_encoder.h"
#include "texture/texture_containers.h"

namespace gtbake {
namespace {

// A 4D table with a step along A and a different value in every theta_o slice (x fastest,
// folded: depth dims[2] * dims[3]).
GtsoTable table4D(const std::vector<int>& dims) {
  GtsoTable t;
  t.file = "gtso4d.f32";
  t.dims = dims;
  t.volume = {dims[0], dims[1], dims[2] * dims[3]};
  for (int w = 0; w < dims[3]; ++w)
    for (int z = 0; z < dims[2]; ++z)
      for (int y = 0; y < dims[1]; ++y)
        for (int x = 0; x < dims[0]; ++x) {
          const double a = x / (dims[0] - 1.0), b = y / (dims[1] - 1.0), r = z / (dims[2] - 1.0);
          const double s = w / (dims[3] - 1.0);
          t.values.push_back(static_cast<float>(
              0.5 + 0.45 * std::tanh((a - 0.3 - 0.4 * b + 0.2 * s) / (0.05 + 0.3 * r))));
        }
  return t;
}

// The extents of table `t` on texture x, y, z in layout l (one tile).
std::array<int, 3> tileOf(const GtsoTable& t, const GtsoLayout& l) {
  return {t.dims[l.axis[0]], t.dims[l.axis[1]], t.dims[l.axis[2]]};
}

// Random inputs plus every combination of the axis ends (t = 0 and 1 on each axis: the texel
// centres on the tiles' faces).
std::vector<std::array<float, 4>> lookupInputs(int count) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f), u11(-1.0f, 1.0f);
  std::vector<std::array<float, 4>> in;
  for (float A : {0.0f, 1.0f})
    for (float cb : {-1.0f, 0.0f, 1.0f})
      for (float rp : {0.0f, 1.0f})
        for (float co : {0.0f, 1.0f}) in.push_back({A, cb, rp, co});
  for (int k = 0; k < count; ++k) in.push_back({u01(rng), u11(rng), u01(rng), u01(rng)});
  return in;
}

TEST(AtlasLayout, ShapeRuleKeepsEveryExtentWithinTheLimit) {
  // The shipped 32^4 table: 4 x 8 tiles, 128x32x256, in each of the 4D candidates.
  const GtsoTable t = table4D({32, 32, 32, 32});
  for (const GtsoLayout& l : layoutCandidates(t)) {
    GtsoLayout a = l;
    a.tilesX = tilesAcrossX(t, l, Layout4D::kAtlas, kAtlasMaxExtent);
    EXPECT_EQ(a.tilesX, 4);
    EXPECT_EQ(layoutVolume(t, a), (std::array<int, 3>{128, 32, 256}));
    EXPECT_EQ(tilesAcrossX(t, l, Layout4D::kFold, kAtlasMaxExtent), 1);
    EXPECT_EQ(layoutVolume(t, l), (std::array<int, 3>{32, 32, 1024}));
  }
  // Other sizes: every extent within 256, the fewest columns (and a fold when it fits).
  for (const std::vector<int>& dims :
       {std::vector<int>{16, 16, 16, 16}, std::vector<int>{36, 36, 36, 36},
        std::vector<int>{32, 32, 24, 30}, std::vector<int>{8, 8, 4, 3}}) {
    const GtsoTable s = table4D(dims);
    const GtsoLayout l = kGtsoIdentityLayout;
    GtsoLayout a = l;
    a.tilesX = tilesAcrossX(s, l, Layout4D::kAtlas, kAtlasMaxExtent);
    const std::array<int, 3> v = layoutVolume(s, a);
    for (int e : v) EXPECT_LE(e, kAtlasMaxExtent) << dims[0] << " " << dims[3];
    EXPECT_GE(a.tilesX * (v[2] / dims[2]), dims[3]);
    EXPECT_LT((a.tilesX - 1) * (kAtlasMaxExtent / dims[2]), dims[3]) << "fewest columns";
  }
  // Too large for 256: one line naming the way out; the fold takes it.
  const GtsoTable big = table4D({40, 40, 40, 40});
  try {
    tilesAcrossX(big, kGtsoIdentityLayout, Layout4D::kAtlas, kAtlasMaxExtent);
    ADD_FAILURE() << "40^4 fits no 256 atlas";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--4d-layout fold"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  EXPECT_EQ(tilesAcrossX(big, kGtsoIdentityLayout, Layout4D::kFold, kAtlasMaxExtent), 1);
  EXPECT_THROW(parseLayout4D("tiles"), Error);
}

// Every texel of the 4D table lands on exactly one texel of the tiled volume and comes back;
// the texels no table texel lands on are exactly those of the tiles past the last slice.
TEST(AtlasLayout, TexelMapRoundTrips) {
  for (const std::vector<int>& dims :
       {std::vector<int>{32, 32, 32, 32}, std::vector<int>{8, 8, 4, 3},
        std::vector<int>{12, 8, 20, 30}}) {
    const GtsoTable t = table4D(dims);
    for (int max : {kAtlasMaxExtent, 16, 64}) {
      for (const GtsoLayout& c : layoutCandidates(t)) {
        GtsoLayout l = c;
        try {
          l.tilesX = tilesAcrossX(t, c, Layout4D::kAtlas, max);
        } catch (const Error&) {
          continue;  // does not fit this limit
        }
        const std::array<int, 3> n = tileOf(t, l), v = layoutVolume(t, l);
        std::vector<int> hits(static_cast<std::size_t>(v[0]) * v[1] * v[2], 0);
        int bad = 0;
        for (int w = 0; w < dims[3]; ++w)
          for (int z = 0; z < n[2]; ++z)
            for (int y = 0; y < n[1]; ++y)
              for (int x = 0; x < n[0]; ++x) {
                const std::array<int, 3> p = tiledTexel(l, n.data(), {x, y, z, w});
                ASSERT_TRUE(p[0] >= 0 && p[0] < v[0] && p[1] >= 0 && p[1] < v[1] && p[2] >= 0 &&
                            p[2] < v[2]);
                ++hits[(static_cast<std::size_t>(p[2]) * v[1] + p[1]) * v[0] + p[0]];
                bad += tableTexel(l, n.data(), p) != std::array<int, 4>{x, y, z, w};
              }
        EXPECT_EQ(bad, 0);
        std::size_t at = 0, empty = 0;
        for (int z = 0; z < v[2]; ++z)
          for (int y = 0; y < v[1]; ++y)
            for (int x = 0; x < v[0]; ++x, ++at) {
              const bool past = tableTexel(l, n.data(), {x, y, z})[3] >= dims[3];
              EXPECT_EQ(hits[at], past ? 0 : 1) << x << " " << y << " " << z;
              empty += past;
            }
        const int tiles = l.tilesX * (v[2] / n[2]);
        EXPECT_EQ(empty, static_cast<std::size_t>(tiles - dims[3]) * n[0] * n[1] * n[2]);
      }
    }
  }
}

// One 4D table packed as the fold and as an atlas with an empty tile (largest extent 16):
// the atlas's BC4 blocks are the fold's reordered and the encoder's own output on the atlas
// texels; lookups of every format through both agree to the last bit; reading the atlas as if
// it were folded does not (so the agreement is not vacuous).
TEST(AtlasLayout, AtlasAndFoldLookupsAgreeToTheLastBit) {
  const GtsoTable t = table4D({8, 8, 4, 3});
  const Bc4Encoder encoder;
  const GtsoLayout l{{1, 2, 0}};
  LayoutChoice fold, atlas;
  for (LayoutChoice* c : {&fold, &atlas}) {
    c->layout = l;
    c->volume = layoutVolume(t, l);
    c->texels = permuteToLayout(t, l);
    c->bc4 = encodeBc4Volume(encoder, c->texels.data(), c->volume[0], c->volume[1], c->volume[2],
                             nullptr);
  }
  packLayoutChoice(t, Layout4D::kFold, 16, &fold);
  packLayoutChoice(t, Layout4D::kAtlas, 16, &atlas);
  ASSERT_EQ(fold.layout.tilesX, 1);
  ASSERT_EQ(atlas.layout.tilesX, 2);
  ASSERT_EQ(atlas.volume, (std::array<int, 3>{16, 4, 16}));
  EXPECT_EQ(atlas.json["packing"]["empty_tiles"], 1);
  const Bc4Volume direct = encodeBc4Volume(encoder, atlas.texels.data(), 16, 4, 16, nullptr);
  EXPECT_EQ(direct.bytes, atlas.bc4.bytes);
  EXPECT_EQ(atlas.bc4.rmse, fold.bc4.rmse);
  // Each format of each packing.
  struct Formats {
    std::vector<std::uint64_t> bc4;
    std::vector<std::uint16_t> r16;
    std::vector<std::uint8_t> r8;
  };
  auto formats = [](const LayoutChoice& c) {
    return Formats{bc4BlockWords(c.bc4.bytes),
                   r16Words(quantizeUnorm(c.texels.data(), c.texels.size(), TexelFormat::kR16)),
                   quantizeUnorm(c.texels.data(), c.texels.size(), TexelFormat::kR8)};
  };
  const Formats ff = formats(fold), fa = formats(atlas);
  auto volumes = [](const LayoutChoice& c, const Formats& f) {
    const auto& v = c.volume;
    return std::array<GtsoVolume, 4>{
        GtsoVolume{GtsoTexelFormat::kFloat32, c.texels.data(), v[0], v[1], v[2]},
        GtsoVolume{GtsoTexelFormat::kBc4, f.bc4.data(), v[0], v[1], v[2]},
        GtsoVolume{GtsoTexelFormat::kR16, f.r16.data(), v[0], v[1], v[2]},
        GtsoVolume{GtsoTexelFormat::kR8, f.r8.data(), v[0], v[1], v[2]}};
  };
  const auto vf = volumes(fold, ff), va = volumes(atlas, fa);
  int differing = 0, misread = 0;
  for (const auto& p : lookupInputs(20000)) {
    for (int k = 0; k < 4; ++k) {
      const float a = gtso4DLookup(va[k], t.dims.data(), p[0], p[1], p[2], p[3], atlas.layout);
      const float f = gtso4DLookup(vf[k], t.dims.data(), p[0], p[1], p[2], p[3], fold.layout);
      differing += std::memcmp(&a, &f, sizeof(float)) != 0;
      const GtsoVolume asFold{va[k].format, va[k].texels, 8, 4, 24};
      misread +=
          std::fabs(gtso4DLookup(asFold, t.dims.data(), p[0], p[1], p[2], p[3], l) - f) > 1e-3f;
    }
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(misread, 1000);
}

// The filter never reads another tile: on an atlas whose tiles are constants (slice w holds
// w + 1, the empty tile 100), each lookup is the lerp of its two slices' constants, at random
// points and at every combination of the axis ends, for the shipped 32^4 shape and the small one.
TEST(AtlasLayout, FilteringStaysInsideATile) {
  for (const std::vector<int>& dims :
       {std::vector<int>{32, 32, 32, 32}, std::vector<int>{8, 8, 4, 3}}) {
    const GtsoTable t = table4D(dims);
    GtsoLayout l{{1, 2, 0}};
    const int max = dims[0] == 8 ? 16 : kAtlasMaxExtent;
    l.tilesX = tilesAcrossX(t, l, Layout4D::kAtlas, max);
    ASSERT_GT(l.tilesX, 1);
    const std::array<int, 3> n = tileOf(t, l), v = layoutVolume(t, l);
    std::vector<float> texels(static_cast<std::size_t>(v[0]) * v[1] * v[2]);
    std::size_t at = 0;
    for (int z = 0; z < v[2]; ++z)
      for (int y = 0; y < v[1]; ++y)
        for (int x = 0; x < v[0]; ++x) {
          const int w = tableTexel(l, n.data(), {x, y, z})[3];
          texels[at++] = w < dims[3] ? static_cast<float>(w + 1) : 100.0f;
        }
    const GtsoVolume volume{GtsoTexelFormat::kFloat32, texels.data(), v[0], v[1], v[2]};
    double worst = 0.0;
    for (const auto& p : lookupInputs(5000)) {
      const GtsoAxisT<float> a = gtso4DAxes(p[0], p[1], p[2], p[3], t.dims.data());
      const float sw = a.t[3] * static_cast<float>(dims[3] - 1);
      const int s0 = std::min(static_cast<int>(sw), dims[3] - 2);
      const double want = s0 + 1 + (sw - s0);  // lerp(s0 + 1, s0 + 2, sw - s0)
      worst = std::max(
          worst, std::fabs(gtso4DLookup(volume, t.dims.data(), p[0], p[1], p[2], p[3], l) - want));
    }
    // Float rounding of the weights' sum times values up to N_w; a neighbouring tile differs by
    // at least 1, so any weight above 1e-5 on it would show.
    EXPECT_LE(worst, 1e-5 * dims[3]) << dims[0];
  }
}

}  // namespace
}  // namespace gtbake
