// One traced tile on disk: everything the sweep's outputs need from its pixels, without loss
// (docs/cluster.md, "Files").
//
// A tile file is "gtbake-tile 2\n", one line of JSON (sweep key, view, tile index, rectangle,
// channel names, rays, payload size and SHA-256), then the payload, little-endian: the
// mask (1 byte per pixel), the escape counts (uint32, counts_per_pixel per pixel, as EscapeImage),
// then every channel that escapeChannels() gives, in its order, as float32 per pixel. Pixels are
// row-major in the tile's rectangle. Since every pixel is traced wholly inside one tile, the
// channel values are the final ones bit for bit, and a merge only places them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "common/image_io.h"
#include "sweep/escape_image.h"

namespace gtbake {

struct TileData {
  std::string key;   // the sweep it belongs to (SweepIdentity::key)
  std::string view;  // the view's name (SweepIdentity::views)
  int index = 0;
  PixelRect rect;
  std::vector<std::uint8_t> mask;
  int counts_per_pixel = 0;
  std::vector<std::uint32_t> counts;
  std::vector<ExrChannel> channels;  // rect.pixels() values each
  std::uint64_t rays = 0;            // camera rays + walk segments traced for these pixels
};

// The tile of `image` (traced over `rect`).
TileData makeTile(const EscapeImage& image, const std::string& key, const std::string& view,
                  int index, const PixelRect& rect);

std::string encodeTile(const TileData& tile);
// Throws gtbake::Error "corrupt tile file <file>: <reason>" on anything malformed.
TileData decodeTile(std::string_view bytes, const std::string& file);

// File name of tile `index` of view `view` inside a tile directory.
std::string tileFileName(const std::string& view, int index);

// Writes atomically (a reader never sees a partial tile).
void writeTile(const std::filesystem::path& path, const TileData& tile);
TileData readTile(const std::filesystem::path& path);

}  // namespace gtbake
