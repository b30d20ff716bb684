// DDS and KTX2 containers for BC4_UNORM, R16_UNORM and R8_UNORM volume textures (docs/export.md
// §2).
//
// Both files hold one mip level of a width × height × depth volume in the texture's memory
// order: BC4 blocks by z slices, in each slice rows of blocks top to bottom, blocks left to right
// (what encodeBc4Volume produces); R16/R8 texels x fastest, little-endian. Field-by-field
// layouts are in docs/export.md.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "texture/texel_format.h"

namespace gtbake {

struct VolumeImage {
  int width = 0;   // texels; BC4: multiple of 4
  int height = 0;  // texels; BC4: multiple of 4
  int depth = 0;   // slices
  // BC4: (width/4)·(height/4)·depth·8 bytes; R16: width·height·depth·2; R8: ·1.
  const std::vector<std::uint8_t>* blocks = nullptr;
  TexelFormat format = TexelFormat::kBc4;  // kBc4, kR16 or kR8
};

// R16_UNORM / R8_UNORM texels of float values: round(clamp(v, 0, 1) * (2^bits - 1)),
// little-endian, same order as `values`.
std::vector<std::uint8_t> quantizeUnorm(const float* values, std::size_t count, TexelFormat format);
// R16 texels as little-endian 16-bit words (GtsoVolume's R16 texels).
std::vector<std::uint16_t> r16Words(const std::vector<std::uint8_t>& texels);
// The inverse read of R16 / R8 texels: q / (2^bits - 1) in float, as the runtime fetch decodes.
std::vector<float> dequantizeUnorm(const std::vector<std::uint8_t>& texels, TexelFormat format);

// "DDS " + DDS_HEADER (DDPF_FOURCC "DX10", DDSCAPS2_VOLUME) + DDS_HEADER_DXT10
// (DXGI_FORMAT_BC4_UNORM = 80, R16_UNORM = 56 or R8_UNORM = 61,
// D3D10_RESOURCE_DIMENSION_TEXTURE3D = 4, arraySize 1) + data.
std::string makeDds(const VolumeImage& image);

// A 2D texture of 32-bit float texels, one mip level, rows top to bottom, texels left to right,
// channels interleaved, little-endian: "DDS " + DDS_HEADER (DDPF_FOURCC "DX10", DDSD_PITCH = row
// bytes) + DDS_HEADER_DXT10 (DXGI_FORMAT_R32_FLOAT = 41 for 1 channel, R32G32B32A32_FLOAT = 2 for
// 4; D3D10_RESOURCE_DIMENSION_TEXTURE2D = 3, arraySize 1) + data (docs/screen_ao.md §8).
std::string makeDdsFloat2d(int width, int height, int channels, const std::vector<float>& texels);

// KTX 2.0 with vkFormat VK_FORMAT_BC4_UNORM_BLOCK (139), VK_FORMAT_R16_UNORM (70) or
// VK_FORMAT_R8_UNORM (9), a KHR_DF_MODEL_BC4 / KHR_DF_MODEL_RGBSDA data format descriptor,
// key/value "KTXwriter" = `writer`, one level at an aligned offset.
std::string makeKtx2(const VolumeImage& image, const std::string& writer);

// A volume read back from a DDS or KTX2 file: its format, extent and payload bytes.
struct VolumeData {
  TexelFormat format = TexelFormat::kBc4;
  int width = 0, height = 0, depth = 0;
  std::vector<std::uint8_t> bytes;  // the payload, in the layout of VolumeImage::blocks
};

// The readers of the files makeDds and makeKtx2 write: one mip level of a BC4/R16/R8 volume,
// every header field checked against what the writers set, the payload exactly the size the
// extent implies. `where` names the file in the one-line gtbake::Error they throw.
VolumeData parseDds(const std::string& bytes, const std::string& where);
VolumeData parseKtx2(const std::string& bytes, const std::string& where);
// readRegularFile (common/input_limits.h) + parseDds / parseKtx2 by the file's extension.
VolumeData readVolumeFile(const std::filesystem::path& path);

}  // namespace gtbake
