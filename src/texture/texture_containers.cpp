#include "texture/texture_containers.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/error.h"
#include "common/input_limits.h"
#include "texture/bc4_block.h"

namespace gtbake {
namespace {

// DDS constants (Microsoft "DDS_HEADER", "DDS_PIXELFORMAT", "DDS_HEADER_DXT10").
constexpr std::uint32_t kDdsMagic = 0x20534444;  // "DDS "
constexpr std::uint32_t kDdsdCaps = 0x1, kDdsdHeight = 0x2, kDdsdWidth = 0x4;
constexpr std::uint32_t kDdsdPixelFormat = 0x1000, kDdsdLinearSize = 0x80000, kDdsdPitch = 0x8;
constexpr std::uint32_t kDdsdDepth = 0x800000;
constexpr std::uint32_t kDdpfFourCc = 0x4;
constexpr std::uint32_t kFourCcDx10 = 0x30315844;  // "DX10"
constexpr std::uint32_t kDdsCapsComplex = 0x8, kDdsCapsTexture = 0x1000;
constexpr std::uint32_t kDdsCaps2Volume = 0x200000;
constexpr std::uint32_t kDxgiFormatBc4Unorm = 80;
constexpr std::uint32_t kDxgiFormatR16Unorm = 56;
constexpr std::uint32_t kDxgiFormatR8Unorm = 61;
constexpr std::uint32_t kDxgiFormatR32Float = 41;
constexpr std::uint32_t kDxgiFormatR32G32B32A32Float = 2;
constexpr std::uint32_t kD3d10ResourceDimensionTexture2d = 3;
constexpr std::uint32_t kD3d10ResourceDimensionTexture3d = 4;

// KTX2 constants (KTX 2.0 specification; Khronos Data Format Specification 1.3).
constexpr std::uint8_t kKtx2Identifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32,
                                              0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
constexpr std::uint32_t kVkFormatBc4UnormBlock = 139;
constexpr std::uint32_t kVkFormatR16Unorm = 70;
constexpr std::uint32_t kVkFormatR8Unorm = 9;
constexpr std::uint32_t kKhrDfModelBc4 = 131;
constexpr std::uint32_t kKhrDfModelRgbsda = 1;
constexpr std::uint32_t kKhrDfPrimariesBt709 = 1;
constexpr std::uint32_t kKhrDfTransferLinear = 1;
constexpr std::uint32_t kKhrDfVersion = 2;        // KDFS 1.3 basic descriptor block
constexpr std::uint32_t kDfdBlockSize = 24 + 16;  // basic block header + one sample

// Little-endian integers of `Bytes` bytes: appended (putLe) or written over s[at..] (setLe).
template <int Bytes>
void putLe(std::string& s, std::uint64_t v) {
  for (int i = 0; i < Bytes; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
template <int Bytes>
void setLe(std::string& s, std::size_t at, std::uint64_t v) {
  for (int i = 0; i < Bytes; ++i) s[at + i] = static_cast<char>((v >> (8 * i)) & 0xFF);
}

// Bytes per texel of an uncompressed format (0 for BC4).
std::uint32_t texelBytes(TexelFormat f) {
  return f == TexelFormat::kR16 ? 2 : (f == TexelFormat::kR8 ? 1 : 0);
}

// Payload bytes of a width x height x depth volume (BC4: 4x4 blocks).
std::size_t payloadBytes(TexelFormat f, int width, int height, int depth) {
  return f == TexelFormat::kBc4
             ? static_cast<std::size_t>(width / 4) * (height / 4) * depth * kBc4BlockBytes
             : static_cast<std::size_t>(width) * height * depth * texelBytes(f);
}

std::size_t checkedSize(const VolumeImage& image) {
  const bool bc4 = image.format == TexelFormat::kBc4;
  if (image.format == TexelFormat::kFloat32) {
    throw Error("texture container: float32 volumes are not written as DDS/KTX2");
  }
  if (image.width <= 0 || image.height <= 0 || image.depth <= 0 || image.blocks == nullptr ||
      (bc4 && (image.width % 4 != 0 || image.height % 4 != 0))) {
    throw Error("texture container: volume size must be positive (multiples of 4 in x, y for BC4)");
  }
  const std::size_t bytes = payloadBytes(image.format, image.width, image.height, image.depth);
  if (image.blocks->size() != bytes) {
    throw Error("texture container: volume data has " + std::to_string(image.blocks->size()) +
                " bytes, expected " + std::to_string(bytes));
  }
  return bytes;
}

std::uint32_t get32(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i)
    v |= static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + i])) << (8 * i);
  return v;
}
std::uint64_t get64(const std::string& s, std::size_t at) {
  return get32(s, at) | static_cast<std::uint64_t>(get32(s, at + 4)) << 32;
}

constexpr std::uint32_t kMaxVolumeExtent = 16384;     // texels per axis a reader accepts
constexpr std::size_t kDdsDataOffset = 4 + 124 + 20;  // magic, DDS_HEADER, DDS_HEADER_DXT10
constexpr std::size_t kKtx2LevelIndex = 80;           // after the header and the index

// The format with DXGI code `dxgi` (DDS) or Vulkan code `vk` (KTX2); throws for any other.
TexelFormat formatOfCode(std::uint32_t code, const std::uint32_t (&codes)[3],
                         const std::string& where) {
  const TexelFormat formats[3] = {TexelFormat::kBc4, TexelFormat::kR16, TexelFormat::kR8};
  for (int i = 0; i < 3; ++i) {
    if (code == codes[i]) return formats[i];
  }
  throw Error(where + ": format code " + std::to_string(code) + " is not BC4, R16 or R8 UNORM");
}

// The volume at [at, at + length) of `bytes` after checking the extent and that length is the
// payload that extent implies.
VolumeData checkedVolume(TexelFormat f, std::uint32_t w, std::uint32_t h, std::uint32_t d,
                         const std::string& bytes, std::uint64_t at, std::uint64_t length,
                         const std::string& where) {
  if (w == 0 || h == 0 || d == 0 || w > kMaxVolumeExtent || h > kMaxVolumeExtent ||
      d > kMaxVolumeExtent) {
    throw Error(where + ": volume extent " + std::to_string(w) + "x" + std::to_string(h) + "x" +
                std::to_string(d) + " outside [1, " + std::to_string(kMaxVolumeExtent) + "]");
  }
  if (f == TexelFormat::kBc4 && (w % 4 != 0 || h % 4 != 0)) {
    throw Error(where + ": BC4 width and height must be multiples of 4");
  }
  const std::size_t expected =
      payloadBytes(f, static_cast<int>(w), static_cast<int>(h), static_cast<int>(d));
  if (length != expected || at > bytes.size() || bytes.size() - at < length) {
    throw Error(where + ": payload of " + std::to_string(length) + " bytes at offset " +
                std::to_string(at) + " does not hold the " + std::to_string(expected) +
                " bytes of the volume in a file of " + std::to_string(bytes.size()));
  }
  VolumeData v;
  v.format = f;
  v.width = static_cast<int>(w);
  v.height = static_cast<int>(h);
  v.depth = static_cast<int>(d);
  v.bytes.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at),
                 bytes.begin() + static_cast<std::ptrdiff_t>(at + length));
  return v;
}

void expect(bool ok, const std::string& where, const char* field) {
  if (!ok) throw Error(where + ": unexpected " + field + " (not a volume gtbake writes)");
}

// The fields of a DDS_HEADER + DDS_HEADER_DXT10 that differ between the files gtbake writes.
struct DdsFields {
  std::uint32_t flags = 0;  // beyond DDSD_CAPS | HEIGHT | WIDTH | PIXELFORMAT
  std::uint32_t width = 0, height = 0, depth = 0, pitch = 0;
  std::uint32_t caps = 0, caps2 = 0;
  std::uint32_t dxgi = 0, dimension = 0;
};

// "DDS " + DDS_HEADER (DDPF_FOURCC "DX10", one mip level) + DDS_HEADER_DXT10 (arraySize 1).
std::string ddsHeader(const DdsFields& f) {
  std::string s;
  putLe<4>(s, kDdsMagic);
  putLe<4>(s, 124);  // DDS_HEADER.dwSize
  putLe<4>(s, kDdsdCaps | kDdsdHeight | kDdsdWidth | kDdsdPixelFormat | f.flags);
  putLe<4>(s, f.height);
  putLe<4>(s, f.width);
  putLe<4>(s, f.pitch);
  putLe<4>(s, f.depth);
  putLe<4>(s, 1);                               // dwMipMapCount
  for (int i = 0; i < 11; ++i) putLe<4>(s, 0);  // dwReserved1
  putLe<4>(s, 32);                              // DDS_PIXELFORMAT.dwSize
  putLe<4>(s, kDdpfFourCc);
  putLe<4>(s, kFourCcDx10);
  for (int i = 0; i < 5; ++i) putLe<4>(s, 0);  // RGB bit count and masks
  putLe<4>(s, f.caps);
  putLe<4>(s, f.caps2);
  putLe<4>(s, 0);  // dwCaps3
  putLe<4>(s, 0);  // dwCaps4
  putLe<4>(s, 0);  // dwReserved2
  putLe<4>(s, f.dxgi);
  putLe<4>(s, f.dimension);
  putLe<4>(s, 0);  // miscFlag
  putLe<4>(s, 1);  // arraySize
  putLe<4>(s, 0);  // miscFlags2: DDS_ALPHA_MODE_UNKNOWN
  return s;
}

}  // namespace

std::vector<std::uint8_t> quantizeUnorm(const float* values, std::size_t count,
                                        TexelFormat format) {
  if (format != TexelFormat::kR16 && format != TexelFormat::kR8) {
    throw Error("quantizeUnorm: only R16 and R8 are unorm formats");
  }
  const std::uint32_t tb = texelBytes(format);
  const double scale = tb == 2 ? 65535.0 : 255.0;
  std::vector<std::uint8_t> out(count * tb);
  for (std::size_t i = 0; i < count; ++i) {
    const double v = std::clamp(static_cast<double>(values[i]), 0.0, 1.0);
    const auto q = static_cast<std::uint32_t>(std::lround(v * scale));
    out[i * tb] = static_cast<std::uint8_t>(q & 0xFF);
    if (tb == 2) out[i * tb + 1] = static_cast<std::uint8_t>(q >> 8);
  }
  return out;
}

std::vector<std::uint16_t> r16Words(const std::vector<std::uint8_t>& texels) {
  std::vector<std::uint16_t> out(texels.size() / 2);
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = static_cast<std::uint16_t>(texels[2 * i] | texels[2 * i + 1] << 8);
  }
  return out;
}

std::vector<float> dequantizeUnorm(const std::vector<std::uint8_t>& texels, TexelFormat format) {
  if (format == TexelFormat::kR16) {
    const std::vector<std::uint16_t> words = r16Words(texels);
    std::vector<float> out(words.size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<float>(words[i]) / 65535.0f;
    return out;
  }
  if (format != TexelFormat::kR8) throw Error("dequantizeUnorm: only R16 and R8 are unorm formats");
  std::vector<float> out(texels.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<float>(texels[i]) / 255.0f;
  return out;
}

std::string makeDds(const VolumeImage& image) {
  const std::size_t bytes = checkedSize(image);
  const bool bc4 = image.format == TexelFormat::kBc4;
  // dwPitchOrLinearSize: BC4 the bytes of one slice of the top level (DirectXTex), else the
  // bytes of one row.
  DdsFields f;
  f.flags = kDdsdDepth | (bc4 ? kDdsdLinearSize : kDdsdPitch);
  f.width = static_cast<std::uint32_t>(image.width);
  f.height = static_cast<std::uint32_t>(image.height);
  f.depth = static_cast<std::uint32_t>(image.depth);
  f.pitch =
      bc4 ? f.width / 4 * (f.height / 4) * kBc4BlockBytes : f.width * texelBytes(image.format);
  f.caps = kDdsCapsTexture | kDdsCapsComplex;
  f.caps2 = kDdsCaps2Volume;
  f.dxgi = bc4 ? kDxgiFormatBc4Unorm
               : (image.format == TexelFormat::kR16 ? kDxgiFormatR16Unorm : kDxgiFormatR8Unorm);
  f.dimension = kD3d10ResourceDimensionTexture3d;
  std::string s = ddsHeader(f);
  s.append(reinterpret_cast<const char*>(image.blocks->data()), bytes);
  return s;
}

std::string makeDdsFloat2d(int width, int height, int channels, const std::vector<float>& texels) {
  if (width <= 0 || height <= 0 || (channels != 1 && channels != 4) ||
      texels.size() != static_cast<std::size_t>(width) * height * channels) {
    throw Error("texture container: a float 2D texture needs 1 or 4 channels of width x height");
  }
  DdsFields f;
  f.flags = kDdsdPitch;
  f.width = static_cast<std::uint32_t>(width);
  f.height = static_cast<std::uint32_t>(height);
  f.depth = 0;
  f.pitch = f.width * 4 * static_cast<std::uint32_t>(channels);
  f.caps = kDdsCapsTexture;
  f.caps2 = 0;
  f.dxgi = channels == 1 ? kDxgiFormatR32Float : kDxgiFormatR32G32B32A32Float;
  f.dimension = kD3d10ResourceDimensionTexture2d;
  std::string s = ddsHeader(f);
  for (const float v : texels) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, sizeof(bits));
    putLe<4>(s, bits);
  }
  return s;
}

std::string makeKtx2(const VolumeImage& image, const std::string& writer) {
  const std::size_t bytes = checkedSize(image);
  const bool bc4 = image.format == TexelFormat::kBc4;
  const std::uint32_t tb = texelBytes(image.format);
  std::string s(reinterpret_cast<const char*>(kKtx2Identifier), sizeof(kKtx2Identifier));
  putLe<4>(s, bc4 ? kVkFormatBc4UnormBlock
                  : (image.format == TexelFormat::kR16 ? kVkFormatR16Unorm : kVkFormatR8Unorm));
  putLe<4>(s, bc4 ? 1 : tb);  // typeSize: block-compressed formats use 1, else the component size
  putLe<4>(s, image.width);
  putLe<4>(s, image.height);
  putLe<4>(s, image.depth);
  putLe<4>(s, 0);  // layerCount: not an array
  putLe<4>(s, 1);  // faceCount
  putLe<4>(s, 1);  // levelCount
  putLe<4>(s, 0);  // supercompressionScheme: none
  const std::size_t index_at = s.size();
  for (int i = 0; i < 4; ++i) putLe<4>(s, 0);  // dfd/kvd offsets and lengths, set below
  putLe<8>(s, 0);                              // sgdByteOffset: no supercompression global data
  putLe<8>(s, 0);                              // sgdByteLength
  const std::size_t level_at = s.size();
  for (int i = 0; i < 3; ++i) putLe<8>(s, 0);  // level 0: byteOffset, byteLength, uncompressed

  // Data format descriptor: dfdTotalSize, then one basic descriptor block with one sample.
  const std::size_t dfd_at = s.size();
  putLe<4>(s, 4 + kDfdBlockSize);
  putLe<4>(s, 0);  // vendorId KHR (0), descriptorType basic (0)
  putLe<4>(s, kKhrDfVersion | kDfdBlockSize << 16);
  putLe<4>(s, (bc4 ? kKhrDfModelBc4 : kKhrDfModelRgbsda) | kKhrDfPrimariesBt709 << 8 |
                  kKhrDfTransferLinear << 16);  // flags 0
  putLe<4>(s, bc4 ? (3 | 3 << 8) : 0);     // texelBlockDimension 4×4×1×1 or 1×1×1×1 (minus 1)
  putLe<4>(s, bc4 ? kBc4BlockBytes : tb);  // bytesPlane0, bytesPlane1..3 = 0
  putLe<4>(s, 0);                          // bytesPlane4..7
  putLe<4>(s, 0 | (bc4 ? 63u : 8 * tb - 1) << 16);  // bitOffset 0, bitLength − 1, channel 0
  putLe<4>(s, 0);                                   // samplePosition 0,0,0,0
  putLe<4>(s, 0);                                   // sampleLower
  putLe<4>(s, bc4 ? 0xFFFFFFFFu : (tb == 2 ? 0xFFFFu : 0xFFu));  // sampleUpper
  const std::size_t dfd_bytes = s.size() - dfd_at;

  // Key/value data: one entry, value NUL-terminated, padded to 4 bytes.
  const std::size_t kvd_at = s.size();
  const std::string key_value = std::string("KTXwriter") + '\0' + writer + '\0';
  putLe<4>(s, static_cast<std::uint32_t>(key_value.size()));
  s += key_value;
  while (s.size() % 4 != 0) s.push_back('\0');
  const std::size_t kvd_bytes = s.size() - kvd_at;

  // Level data aligned to lcm(texel block size, 4): 8 for BC4, 4 for R16/R8.
  while (s.size() % (bc4 ? kBc4BlockBytes : 4) != 0) s.push_back('\0');
  const std::size_t data_at = s.size();
  s.append(reinterpret_cast<const char*>(image.blocks->data()), bytes);

  setLe<4>(s, index_at, static_cast<std::uint32_t>(dfd_at));
  setLe<4>(s, index_at + 4, static_cast<std::uint32_t>(dfd_bytes));
  setLe<4>(s, index_at + 8, static_cast<std::uint32_t>(kvd_at));
  setLe<4>(s, index_at + 12, static_cast<std::uint32_t>(kvd_bytes));
  setLe<8>(s, level_at, data_at);
  setLe<8>(s, level_at + 8, bytes);
  setLe<8>(s, level_at + 16, bytes);
  return s;
}

VolumeData parseDds(const std::string& bytes, const std::string& where) {
  expect(bytes.size() >= kDdsDataOffset, where, "size (shorter than the DDS headers)");
  expect(get32(bytes, 0) == kDdsMagic && get32(bytes, 4) == 124, where, "DDS magic or header size");
  expect(get32(bytes, 76) == 32 && (get32(bytes, 80) & kDdpfFourCc) != 0 &&
             get32(bytes, 84) == kFourCcDx10,
         where, "pixel format (DX10 FourCC)");
  expect((get32(bytes, 112) & kDdsCaps2Volume) != 0 && get32(bytes, 28) <= 1, where,
         "caps (one mip level of a volume)");
  expect(get32(bytes, 132) == kD3d10ResourceDimensionTexture3d && get32(bytes, 140) == 1, where,
         "DX10 dimension or array size");
  const TexelFormat f = formatOfCode(
      get32(bytes, 128), {kDxgiFormatBc4Unorm, kDxgiFormatR16Unorm, kDxgiFormatR8Unorm}, where);
  return checkedVolume(f, get32(bytes, 16), get32(bytes, 12), get32(bytes, 24), bytes,
                       kDdsDataOffset, bytes.size() - kDdsDataOffset, where);
}

VolumeData parseKtx2(const std::string& bytes, const std::string& where) {
  expect(
      bytes.size() >= kKtx2LevelIndex + 24 &&
          bytes.compare(0, sizeof(kKtx2Identifier), reinterpret_cast<const char*>(kKtx2Identifier),
                        sizeof(kKtx2Identifier)) == 0,
      where, "KTX2 identifier");
  expect(get32(bytes, 32) == 0 && get32(bytes, 36) == 1 && get32(bytes, 40) == 1 &&
             get32(bytes, 44) == 0,
         where, "layer, face or level count or supercompression");
  const TexelFormat f = formatOfCode(
      get32(bytes, 12), {kVkFormatBc4UnormBlock, kVkFormatR16Unorm, kVkFormatR8Unorm}, where);
  const std::uint64_t length = get64(bytes, kKtx2LevelIndex + 8);
  expect(get64(bytes, kKtx2LevelIndex + 16) == length, where, "uncompressed level length");
  return checkedVolume(f, get32(bytes, 20), get32(bytes, 24), get32(bytes, 28), bytes,
                       get64(bytes, kKtx2LevelIndex), length, where);
}

VolumeData readVolumeFile(const std::filesystem::path& path) {
  const std::string bytes = readRegularFile(path);
  if (path.extension() == ".ktx2") return parseKtx2(bytes, path.string());
  return parseDds(bytes, path.string());
}

}  // namespace gtbake
