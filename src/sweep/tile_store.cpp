#include "sweep/tile_store.h"

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/input_limits.h"
#include "common/sha256.h"
#include "common/text_escape.h"

namespace gtbake {

namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "tile files are little-endian; add byte swapping for this machine");

constexpr std::string_view kMagic = "gtbake-tile 2\n";

template <typename T>
void append(std::string* out, const std::vector<T>& values) {
  out->append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

template <typename T>
std::vector<T> take(std::string_view* in, std::size_t count, const std::string& file) {
  if (in->size() < count * sizeof(T)) throw Error("corrupt tile file " + file + ": truncated");
  std::vector<T> values(count);
  std::memcpy(values.data(), in->data(), count * sizeof(T));
  in->remove_prefix(count * sizeof(T));
  return values;
}

std::string payload(const TileData& tile) {
  std::string bytes;
  append(&bytes, tile.mask);
  append(&bytes, tile.counts);
  for (const ExrChannel& c : tile.channels) append(&bytes, c.pixels);
  return bytes;
}

}  // namespace

TileData makeTile(const EscapeImage& image, const std::string& key, const std::string& view,
                  int index, const PixelRect& rect) {
  TileData tile;
  tile.key = key;
  tile.view = view;
  tile.index = index;
  tile.rect = rect;
  tile.mask = image.mask;
  tile.counts_per_pixel = 2 * (image.settings.bounces + 1);
  tile.counts = image.counts;
  tile.channels = escapeChannels(image);
  tile.rays = image.rays;
  return tile;
}

std::string encodeTile(const TileData& tile) {
  const std::string body = payload(tile);
  nlohmann::ordered_json header;
  header["key"] = tile.key;
  header["view"] = tile.view;
  header["index"] = tile.index;
  header["rect"] = {tile.rect.x0, tile.rect.y0, tile.rect.x1, tile.rect.y1};
  header["counts_per_pixel"] = tile.counts_per_pixel;
  nlohmann::ordered_json names = nlohmann::ordered_json::array();
  for (const ExrChannel& c : tile.channels) names.push_back(c.name);
  header["channels"] = std::move(names);
  header["rays"] = tile.rays;
  header["payload_bytes"] = body.size();
  header["payload_sha256"] = sha256Hex(body);
  std::string bytes(kMagic);
  bytes += header.dump();
  bytes += '\n';
  bytes += body;
  return bytes;
}

TileData decodeTile(std::string_view bytes, const std::string& file) {
  const std::string corrupt = "corrupt tile file " + file + ": ";
  if (bytes.substr(0, kMagic.size()) != kMagic) throw Error(corrupt + "not a gtbake tile");
  bytes.remove_prefix(kMagic.size());
  const std::size_t eol = bytes.find('\n');
  if (eol == std::string_view::npos) throw Error(corrupt + "truncated header");
  TileData tile;
  std::vector<std::string> names;
  std::size_t payload_bytes = 0;
  std::string payload_sha;
  try {
    // Every number bounded where it is read (docs/limits.md §Values): corners inside a sweep image,
    // two counts per bounce and pixel.
    const nlohmann::json header = parseJsonText(bytes.substr(0, eol), file);
    tile.key = header.at("key").get<std::string>();
    tile.view = header.at("view").get<std::string>();
    tile.index = static_cast<int>(jsonInteger(header, "index", 0, INT32_MAX, corrupt + "header"));
    const nlohmann::json& rect = header.at("rect");
    if (!rect.is_array() || rect.size() != 4) throw Error(corrupt + "bad rectangle");
    int corner[4];
    for (int k = 0; k < 4; ++k) {
      const nlohmann::json one = {{"rect", rect[k]}};
      corner[k] = static_cast<int>(jsonInteger(one, "rect", 0, kMaxImageSide, corrupt + "header"));
    }
    tile.rect = PixelRect{corner[0], corner[1], corner[2], corner[3]};
    tile.counts_per_pixel = static_cast<int>(
        jsonInteger(header, "counts_per_pixel", 0, 2 * (kMaxSweepBounces + 1), corrupt + "header"));
    names = header.at("channels").get<std::vector<std::string>>();
    tile.rays = header.at("rays").get<std::uint64_t>();
    payload_bytes = header.at("payload_bytes").get<std::size_t>();
    payload_sha = header.at("payload_sha256").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    throw Error(corrupt + "bad header (" + e.what() + ")");
  }
  if (tile.rect.width() <= 0 || tile.rect.height() <= 0 || tile.counts_per_pixel < 0) {
    throw Error(corrupt + "bad rectangle or count layout");
  }
  bytes.remove_prefix(eol + 1);
  if (bytes.size() != payload_bytes) throw Error(corrupt + "wrong payload size (truncated?)");
  if (sha256Hex(bytes) != payload_sha) throw Error(corrupt + "payload SHA-256 mismatch");
  const std::size_t pixels = tile.rect.pixels();
  tile.mask = take<std::uint8_t>(&bytes, pixels, file);
  tile.counts = take<std::uint32_t>(&bytes, pixels * tile.counts_per_pixel, file);
  for (const std::string& name : names) {
    tile.channels.push_back({name, take<float>(&bytes, pixels, file)});
  }
  if (!bytes.empty()) throw Error(corrupt + "trailing bytes");
  return tile;
}

std::string tileFileName(const std::string& view, int index) {
  char number[16];
  std::snprintf(number, sizeof(number), "%05d", index);
  return fileSlug(view) + "." + number + ".tile";  // docs/limits.md §Names in outputs
}

void writeTile(const std::filesystem::path& path, const TileData& tile) {
  writeFileAtomically(path, encodeTile(tile));
}

TileData readTile(const std::filesystem::path& path) {
  return decodeTile(readFile(path), path.string());
}

}  // namespace gtbake
