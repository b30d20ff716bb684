#include "sweep/tile_plan.h"

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace gtbake {

namespace {

// SplitMix64's finaliser: a fixed bijective scramble of 64 bits.
std::uint64_t scramble(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

}  // namespace

std::vector<int> TilePlan::tilesOfShard(int shard) const {
  std::vector<int> mine;
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    if (shard_of[t] == shard) mine.push_back(static_cast<int>(t));
  }
  return mine;
}

TilePlan planTiles(int views, int width, int height, int shards) {
  TilePlan plan;
  plan.width = width;
  plan.height = height;
  plan.shards = shards;
  const int columns = (width + kTileSide - 1) / kTileSide;
  const int rows = (height + kTileSide - 1) / kTileSide;
  std::vector<std::uint64_t> load(static_cast<std::size_t>(shards), 0);
  for (int s = 0; s < views; ++s) {
    plan.first_of.push_back(static_cast<int>(plan.tiles.size()));
    plan.tiles_of.push_back(columns * rows);
    for (int index = 0; index < columns * rows; ++index) {
      const int x0 = (index % columns) * kTileSide;
      const int y0 = (index / columns) * kTileSide;
      plan.tiles.push_back(
          {s, index,
           PixelRect{x0, y0, std::min(x0 + kTileSide, width), std::min(y0 + kTileSide, height)}});
    }
    std::vector<int> order(static_cast<std::size_t>(columns * rows));
    std::iota(order.begin(), order.end(), 0);
    const std::uint64_t view_key = scramble(static_cast<std::uint64_t>(s));
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      const std::uint64_t ka = scramble(view_key ^ static_cast<std::uint64_t>(a));
      const std::uint64_t kb = scramble(view_key ^ static_cast<std::uint64_t>(b));
      return ka != kb ? ka < kb : a < b;
    });
    plan.shard_of.resize(plan.tiles.size());
    for (int index : order) {
      const auto lightest = std::min_element(load.begin(), load.end());
      const int shard = static_cast<int>(lightest - load.begin());
      const int t = plan.first_of[s] + index;
      plan.shard_of[t] = shard;
      *lightest += plan.tiles[t].rect.pixels();
    }
  }
  return plan;
}

}  // namespace gtbake
