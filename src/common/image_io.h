// Image files: multi-channel float OpenEXR (read and write) and 8-bit PNG previews.
//
// EXR files are written with ZIP compression and no time-stamp attributes, so the same pixels give
// the same bytes. Channels are stored as 32-bit float, in the order given (OpenEXR sorts them by
// name in the header). All writes are atomic (see atomic_file.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace gtbake {

struct ExrChannel {
  std::string name;
  std::vector<float> pixels;  // width*height, row-major, row 0 at the top
};

struct ExrImage {
  int width = 0;
  int height = 0;
  std::map<std::string, std::vector<float>> channels;
  std::map<std::string, std::string> attributes;  // string attributes (e.g. provenance)

  // The named channel or a gtbake::Error naming the file and the channel.
  const std::vector<float>& channel(const std::string& name, const std::string& file) const;
};

void writeExr(const std::filesystem::path& path, int width, int height,
              const std::vector<ExrChannel>& channels,
              const std::map<std::string, std::string>& attributes = {});

// Reads every channel as float. Throws gtbake::Error with a one-line reason on any failure.
ExrImage readExr(const std::filesystem::path& path);

// 8-bit PNGs (1 = gray, 3 = RGB), row-major, row 0 at the top.
void writePng(const std::filesystem::path& path, int width, int height, int components,
              const std::vector<std::uint8_t>& pixels);

// Maps values linearly from [lo, hi] to 0..255 (clamped); NaN maps to 0.
std::vector<std::uint8_t> toGray8(const std::vector<float>& values, float lo, float hi);

// Maps values from [lo, hi] through a perceptual blue-to-yellow ramp (viridis control points),
// three bytes per value; for error maps and table slices.
std::vector<std::uint8_t> toViridis8(const std::vector<float>& values, float lo, float hi);

}  // namespace gtbake
