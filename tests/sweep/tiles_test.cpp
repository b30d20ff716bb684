// Tiles, shards, merge and resume (docs/cluster.md, docs/reproducibility.md): a pixel's values do
// not depend on which rectangle, shard or run traced it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "common/error.h"
#include "scene/procedural_scenes.h"
#include "support/test_scenes.h"
#include "sweep/embree_tracer.h"
#include "sweep/escape_image.h"
#include "sweep/tile_plan.h"
#include "sweep/tile_store.h"

namespace gtbake {
namespace {

// Tracing a rectangle gives, pixel for pixel and channel for channel, the bits of the whole image.
TEST(Tiles, RectangleEqualsTheSamePixelsOfTheWholeImage) {
  const Scene scene = makeSphereOnPlaneScene(1.0);
  const EmbreeTracer tracer(scene);
  WalkSettings settings;
  settings.spp = 8;
  settings.specular_roughness = {0.0, 0.4};
  settings.specular_spp = 8;
  settings.transfer = true;  // the transfer channels too (docs/sweep.md, "Transfer")
  settings.view_key = viewStreamKey("spheres");
  const int width = 23;
  const int height = 17;
  const EscapeImage whole =
      traceEscapeImage(tracer, scene.camera, width, height, settings, "", false);
  const PixelRect rect{5, 3, 19, 11};
  const EscapeImage part =
      traceEscapeImage(tracer, scene.camera, width, height, rect, settings, "", false);
  ASSERT_EQ(part.width, rect.width());
  ASSERT_EQ(part.height, rect.height());
  const std::vector<ExrChannel> a = escapeChannels(whole);
  const std::vector<ExrChannel> b = escapeChannels(part);
  ASSERT_EQ(a.size(), b.size());
  std::size_t unmasked = 0;
  for (std::size_t c = 0; c < a.size(); ++c) {
    ASSERT_EQ(a[c].name, b[c].name);
    for (int j = rect.y0; j < rect.y1; ++j) {
      for (int i = rect.x0; i < rect.x1; ++i) {
        const float full = a[c].pixels[static_cast<std::size_t>(j) * width + i];
        const float tile =
            b[c].pixels[static_cast<std::size_t>(j - rect.y0) * rect.width() + (i - rect.x0)];
        ASSERT_EQ(full, tile) << a[c].name << " at (" << i << ", " << j << ")";
      }
    }
  }
  for (std::uint8_t m : part.mask) unmasked += m;
  EXPECT_GT(unmasked, rect.pixels() / 2) << "the rectangle should mostly see geometry";
}

// Every pixel of every view lies in exactly one tile, every tile in exactly one shard, and the
// shards' pixel counts (the expected cost) differ by at most one tile.
TEST(Tiles, PlanCoversEveryPixelOnceAndBalancesShards) {
  for (int shards : {1, 3, 4, 7}) {
    const int width = 200;
    const int height = 75;
    const TilePlan plan = planTiles(3, width, height, shards);
    std::vector<int> covered(3 * width * height, 0);
    std::vector<std::size_t> pixels(shards, 0);
    for (std::size_t t = 0; t < plan.tiles.size(); ++t) {
      const Tile& tile = plan.tiles[t];
      ASSERT_GE(plan.shard_of[t], 0);
      ASSERT_LT(plan.shard_of[t], shards);
      pixels[plan.shard_of[t]] += tile.rect.pixels();
      for (int j = tile.rect.y0; j < tile.rect.y1; ++j) {
        for (int i = tile.rect.x0; i < tile.rect.x1; ++i)
          ++covered[(tile.view * height + j) * width + i];
      }
    }
    EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int c) { return c == 1; }));
    const auto [lo, hi] = std::minmax_element(pixels.begin(), pixels.end());
    EXPECT_LE(*hi - *lo, static_cast<std::size_t>(kTileSide * kTileSide)) << shards << " shards";
    std::size_t mine = 0;
    for (int s = 0; s < shards; ++s) mine += plan.tilesOfShard(s).size();
    EXPECT_EQ(mine, plan.tiles.size());
  }
  // The plan is a pure function of its arguments.
  EXPECT_EQ(planTiles(2, 100, 90, 4).shard_of, planTiles(2, 100, 90, 4).shard_of);
}

// A tile survives encoding bit for bit; a flipped payload byte or a truncation is refused.
TEST(Tiles, TileFileRoundTripsAndRefusesDamage) {
  TileData tile;
  tile.key = "k";
  tile.view = "wells";
  tile.index = 3;
  tile.rect = PixelRect{32, 0, 35, 2};
  tile.mask = {1, 0, 1, 1, 1, 0};
  tile.counts_per_pixel = 2;
  tile.counts = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0xffffffffu};
  tile.channels = {{"A", {0.5f, 0.0f, 1.0f, 0.25f, -0.0f, 3e-38f}}, {"S010", {1, 2, 3, 4, 5, 6}}};
  tile.rays = 12345;
  const std::string bytes = encodeTile(tile);
  const TileData back = decodeTile(bytes, "t");
  EXPECT_EQ(back.key, tile.key);
  EXPECT_EQ(back.view, tile.view);
  EXPECT_EQ(back.index, tile.index);
  EXPECT_EQ(back.rect.x1, tile.rect.x1);
  EXPECT_EQ(back.mask, tile.mask);
  EXPECT_EQ(back.counts, tile.counts);
  ASSERT_EQ(back.channels.size(), 2u);
  EXPECT_EQ(back.channels[1].name, "S010");
  EXPECT_EQ(0, std::memcmp(back.channels[0].pixels.data(), tile.channels[0].pixels.data(), 24));
  EXPECT_EQ(back.rays, tile.rays);
  std::string flipped = bytes;
  flipped[flipped.size() - 3] ^= 1;
  EXPECT_THROW(decodeTile(flipped, "t"), Error);
  EXPECT_THROW(decodeTile(bytes.substr(0, bytes.size() - 1), "t"), Error);
  EXPECT_THROW(decodeTile("gtbake-tile 2\n{", "t"), Error);
}

}  // namespace
}  // namespace gtbake
