#include "validate_gtso/gtso_lookup.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "common/error.h"
#include "common/progress.h"
#include "export/bc4_block.h"
#include "export/bc4_encoder.h"
#include "export/export_inputs.h"
#include "export/runtime/gtso_lookup.h"

namespace gtbake {

namespace {

namespace fs = std::filesystem;

// One table behind the runtime-lookup API of src/export/runtime/gtso_lookup.h (the code the
// header and shader includes ship): its texels (float, or BC4 blocks as uint64) and sizes.
class RuntimeTables final : public GtsoLookup {
 public:
  RuntimeTables(GtsoTexelFormat format, const GtsoTable& t3, const GtsoTable& t4,
                const std::vector<std::uint8_t>* bc4_3, const std::vector<std::uint8_t>* bc4_4)
      : format_(format) {
    for (int a = 0; a < 3; ++a) {
      size3_[a] = t3.dims[a];
      volume3_[a] = t3.volume[a];
      volume4_[a] = t4.volume[a];
    }
    for (int a = 0; a < 4; ++a) size4_[a] = t4.dims[a];
    if (format == GtsoTexelFormat::kBc4) {
      blocks3_ = toBlocks(*bc4_3);
      blocks4_ = toBlocks(*bc4_4);
    } else {
      floats3_ = t3.values;
      floats4_ = t4.values;
    }
  }

  float s3(float A, float cos_beta, float r_p) const override {
    return gtso3DLookup(volume(3), size3_, A, cos_beta, r_p);
  }
  float s4(float A, float cos_beta, float r_p, float cos_theta_o) const override {
    return gtso4DLookup(volume(4), size4_, A, cos_beta, r_p, cos_theta_o);
  }

 private:
  static std::vector<std::uint64_t> toBlocks(const std::vector<std::uint8_t>& bytes) {
    std::vector<std::uint64_t> blocks(bytes.size() / kBc4BlockBytes, 0);
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      for (int i = 0; i < kBc4BlockBytes; ++i) {
        blocks[b] |= static_cast<std::uint64_t>(bytes[kBc4BlockBytes * b + i]) << (8 * i);
      }
    }
    return blocks;
  }
  GtsoVolume volume(int dims) const {
    const int* v = dims == 3 ? volume3_ : volume4_;
    const void* texels =
        format_ == GtsoTexelFormat::kBc4
            ? static_cast<const void*>(dims == 3 ? blocks3_.data() : blocks4_.data())
            : static_cast<const void*>(dims == 3 ? floats3_.data() : floats4_.data());
    return GtsoVolume{format_, texels, v[0], v[1], v[2]};
  }

  GtsoTexelFormat format_;
  int size3_[3] = {0, 0, 0};
  int size4_[4] = {0, 0, 0, 0};
  int volume3_[3] = {0, 0, 0};
  int volume4_[3] = {0, 0, 0};
  std::vector<std::uint64_t> blocks3_, blocks4_;
  std::vector<float> floats3_, floats4_;
};

std::uint32_t le32(const std::string& bytes, std::size_t offset) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) {
    v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[offset + i])) << (8 * i);
  }
  return v;
}

// The blocks of a BC4 volume DDS as makeDds writes it (magic, DDS_HEADER, DX10 header, blocks).
std::vector<std::uint8_t> readDdsBlocks(const fs::path& path, const std::array<int, 3>& volume) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  constexpr std::size_t kHeader = 4 + 124 + 20;  // "DDS ", DDS_HEADER, DDS_HEADER_DXT10
  constexpr std::uint32_t kDxgiBc4Unorm = 80;
  const std::size_t blocks =
      static_cast<std::size_t>(volume[0] / 4) * (volume[1] / 4) * volume[2] * kBc4BlockBytes;
  if (bytes.size() != kHeader + blocks || bytes.compare(0, 4, "DDS ") != 0 ||
      le32(bytes, 128) != kDxgiBc4Unorm ||
      le32(bytes, 12) != static_cast<std::uint32_t>(volume[1]) ||
      le32(bytes, 16) != static_cast<std::uint32_t>(volume[0]) ||
      le32(bytes, 24) != static_cast<std::uint32_t>(volume[2])) {
    throw Error(path.string() + ": not the BC4_UNORM volume of the gtso tables (" +
                std::to_string(volume[0]) + "x" + std::to_string(volume[1]) + "x" +
                std::to_string(volume[2]) + "); rerun gtbake export");
  }
  return std::vector<std::uint8_t>(bytes.begin() + kHeader, bytes.end());
}

std::vector<std::uint8_t> encodeBlocks(const Bc4Encoder& encoder, const GtsoTable& t,
                                       const char* label, bool progress) {
  Progress bar(label, static_cast<std::uint64_t>(t.volume[0] / 4) * (t.volume[1] / 4) * t.volume[2],
               progress);
  Bc4Volume v =
      encodeBc4Volume(encoder, t.values.data(), t.volume[0], t.volume[1], t.volume[2], &bar);
  bar.finish();
  return std::move(v.bytes);
}

}  // namespace

TablesLookups makeTablesLookups(const fs::path& luts, bool encode_bc4, bool progress) {
  const GtsoInput gtso = readGtsoInput(luts / "gtso");
  const fs::path dds3 = luts / "gtso3d.dds";
  const fs::path dds4 = luts / "gtso4d.dds";
  std::vector<std::uint8_t> blocks3;
  std::vector<std::uint8_t> blocks4;
  TablesLookups out;
  if (!encode_bc4 && fs::exists(dds3) && fs::exists(dds4)) {
    blocks3 = readDdsBlocks(dds3, gtso.table3d.volume);
    blocks4 = readDdsBlocks(dds4, gtso.table4d.volume);
    out.info.bc4_source = "gtso3d.dds, gtso4d.dds";
  } else {
    const Bc4Encoder encoder;
    blocks3 = encodeBlocks(encoder, gtso.table3d, "BC4 3D table", progress);
    blocks4 = encodeBlocks(encoder, gtso.table4d, "BC4 4D table", progress);
    out.info.bc4_source = "gtso/gtso3d.f32, gtso4d.f32 encoded by the export's BC4 encoder";
  }
  out.bc4 = std::make_unique<RuntimeTables>(GtsoTexelFormat::kBc4, gtso.table3d, gtso.table4d,
                                            &blocks3, &blocks4);
  out.floats = std::make_unique<RuntimeTables>(GtsoTexelFormat::kFloat32, gtso.table3d,
                                               gtso.table4d, nullptr, nullptr);
  out.info.u_table_fit = gtso.u;
  for (double k : gtso.s3_closed_form) out.info.s3_closed_form.push_back(static_cast<float>(k));
  return out;
}

}  // namespace gtbake
