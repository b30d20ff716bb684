// DDS and KTX2 containers for BC4_UNORM volume textures (SPEC §1.5).
//
// Both files hold one mip level of a width × height × depth volume whose BC4 blocks are in the
// texture's memory order: z slices, in each slice rows of blocks top to bottom, blocks left to
// right (what encodeBc4Volume produces). Field-by-field layouts are in docs/export.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace gtbake {

struct Bc4VolumeImage {
  int width = 0;                                      // texels; multiple of 4
  int height = 0;                                     // texels; multiple of 4
  int depth = 0;                                      // slices
  const std::vector<std::uint8_t>* blocks = nullptr;  // (width/4)·(height/4)·depth·8 bytes
};

// "DDS " + DDS_HEADER (DDPF_FOURCC "DX10", DDSCAPS2_VOLUME) + DDS_HEADER_DXT10
// (DXGI_FORMAT_BC4_UNORM = 80, D3D10_RESOURCE_DIMENSION_TEXTURE3D = 4, arraySize 1) + blocks.
std::string makeDds(const Bc4VolumeImage& image);

// KTX 2.0 with vkFormat VK_FORMAT_BC4_UNORM_BLOCK (139), a KHR_DF_MODEL_BC4 data format
// descriptor, key/value "KTXwriter" = `writer`, one level at an 8-byte aligned offset.
std::string makeKtx2(const Bc4VolumeImage& image, const std::string& writer);

}  // namespace gtbake
