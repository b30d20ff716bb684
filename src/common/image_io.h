// Image files: multi-channel float OpenEXR (read and write) and 8-bit PNG previews.
//
// EXR files are written with RLE compression (lossless; about 2.5 times less CPU to encode than ZIP
// on the sweep's noisy float channels, for files about 1.4 times larger: docs/sweep.md §4) and no
// time-stamp attributes, so the same pixels give the same bytes. Channels are stored as 32-bit
// float, in the order given (OpenEXR sorts them by name in the header). All writes are atomic (see
// atomic_file.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
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

// What a reader knows about an EXR before decoding it (0 = not known); checked against the
// header before any pixel memory is allocated.
struct ExrExpect {
  int width = 0;
  int height = 0;
  std::string source = "the provenance";  // where the expectation comes from, for the error
};

// The EXR file's bytes (an in-memory encoding; writeExr writes them through the checked writer).
std::string encodeExr(int width, int height, const std::vector<ExrChannel>& channels,
                      const std::map<std::string, std::string>& attributes = {});

// Reads every channel as float. Refuses, before allocating pixels: a data window not starting at
// (0, 0), sides over 8192, a size other than `expect`, or a window far larger than the file's
// bytes could encode. Throws gtbake::Error with a one-line reason on any failure. Bytes this
// process decoded before are not decoded again: their image is kept by SHA-256 (up to 1 GiB of
// pixels, oldest dropped first), which in `gtbake all` saves every later stage's decoding of the
// sweep.
ExrImage decodeExr(const std::string& bytes, const std::string& name, const ExrExpect& expect = {});
ExrImage readExr(const std::filesystem::path& path, const ExrExpect& expect = {});

struct OutputManifest;

// decodeExr of the file `file` of an output set, read and checked against its manifest
// (OutputManifest::readVerified). The verified bytes have the manifest's SHA-256, so that is the
// decoded-image key: the bytes are hashed once per read, not again for the key. The image is
// shared with the cache, not copied (docs/performance.md "Decoded images"). A file this process
// verified before, whose device, inode, size, modification and status-change times are the same
// and were already a second old when it was read, is not read again: its image is the cached one.
// `name` names the file in errors.
std::shared_ptr<const ExrImage> readVerifiedExr(const OutputManifest& manifest,
                                                const std::string& file, const std::string& name,
                                                const ExrExpect& expect = {});

// readVerifiedExr's calls so far in this process: those that read the file, and those that found
// it unchanged since a verified read and took its image from the cache.
struct ExrReadCounts {
  std::size_t read = 0;
  std::size_t unchanged = 0;
};
ExrReadCounts exrReadCounts();

// 8-bit PNGs (1 = gray, 3 = RGB), row-major, row 0 at the top, encoded in memory and written
// through the checked atomic writer (stb's own file writer does not report a failed write).
std::string encodePng(int width, int height, int components,
                      const std::vector<std::uint8_t>& pixels);
void writePng(const std::filesystem::path& path, int width, int height, int components,
              const std::vector<std::uint8_t>& pixels);

// Maps values linearly from [lo, hi] to 0..255 (clamped); NaN maps to 0.
std::vector<std::uint8_t> toGray8(const std::vector<float>& values, float lo, float hi);

// Maps values from [lo, hi] through a perceptual blue-to-yellow ramp (viridis control points),
// three bytes per value; for error maps and table slices.
std::vector<std::uint8_t> toViridis8(const std::vector<float>& values, float lo, float hi);

}  // namespace gtbake
