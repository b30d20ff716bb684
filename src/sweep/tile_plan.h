// The partition of a sweep's work: every pixel of every view in exactly one tile, every tile in
// exactly one shard (docs/cluster.md). A pure function of (view count, resolution, shard count):
// it does not depend on the thread count, the machine or the scenes' contents, so every shard of
// a run computes the same plan on its own.
#pragma once

#include <string>
#include <vector>

#include "sweep/escape_image.h"

namespace gtbake {

// Tiles are squares of kTileSide pixels (clipped at the image's right and bottom edges): 1024
// pixels × spp walks is 0.1–1 s of tracing at the defaults, so a checkpoint loses little and
// the per-tile file and bookkeeping cost (≈ 1 ms) stays below 1%.
inline constexpr int kTileSide = 32;

struct Tile {
  int view = 0;   // index into the sweep's view list
  int index = 0;  // row-major among the view's tiles
  PixelRect rect;
};

struct TilePlan {
  int width = 0;
  int height = 0;
  int shards = 1;
  std::vector<Tile> tiles;    // view by view, row-major within a view
  std::vector<int> shard_of;  // per tile: the shard that traces it
  std::vector<int> tiles_of;  // per view: its tile count
  std::vector<int> first_of;  // per view: index of its first tile in `tiles`

  // The tiles of shard `shard`, view by view in row-major order.
  std::vector<int> tilesOfShard(int shard) const;
  // The global index of (view, index).
  int find(int view, int index) const { return first_of[view] + index; }
};

// Cuts each view's width × height image into kTileSide tiles and deals them to `shards` shards,
// balanced by expected cost: a tile's expected cost is its pixel count (every pixel traces the
// same spp walks of up to K + 1 segments; what a pixel actually costs depends on geometry that
// the plan must not depend on). Each view's tiles are taken in a fixed pseudo-random order (a
// hash of view and tile index), so every shard's share is spread over the whole image rather
// than over a band of sky or of a deep cavity, and each goes to the shard with the least expected
// cost so far (ties: the lowest index). Each shard then gets ⌊T/N⌋ or ⌈T/N⌉ of every view's T
// tiles.
TilePlan planTiles(int views, int width, int height, int shards);

}  // namespace gtbake
