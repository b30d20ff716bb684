#include "validate_gtso/gtso_lookup.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/progress.h"
#include "export/bc4_block.h"
#include "export/bc4_encoder.h"
#include "export/bc4_layout.h"
#include "export/export_inputs.h"
#include "export/runtime/gtso_lookup.h"
#include "export/texture_containers.h"

namespace gtbake {

namespace {

namespace fs = std::filesystem;

// One table behind the runtime-lookup API of src/export/runtime/gtso_lookup.h (the code the
// header and shader includes ship): its texels in one format and its sizes.
class RuntimeTables final : public GtsoLookup {
 public:
  // bytes3/bytes4: the volumes' payloads as export writes them (BC4 blocks, little-endian R16,
  // R8); unused for float32, which reads the tables' floats.
  // layout3/4: the volumes' texture layouts (float32 reads the tables in table order).
  RuntimeTables(GtsoTexelFormat format, const GtsoTable& t3, const GtsoTable& t4,
                const std::vector<std::uint8_t>* bytes3, const std::vector<std::uint8_t>* bytes4,
                const GtsoLayout& layout3, const GtsoLayout& layout4)
      : format_(format), layout3_(layout3), layout4_(layout4) {
    const std::array<int, 3> v3 = layoutVolume(t3, layout3), v4 = layoutVolume(t4, layout4);
    for (int a = 0; a < 3; ++a) {
      size3_[a] = t3.dims[a];
      volume3_[a] = v3[a];
      volume4_[a] = v4[a];
    }
    for (int a = 0; a < 4; ++a) size4_[a] = t4.dims[a];
    load(t3, bytes3, 0);
    load(t4, bytes4, 1);
  }

  float s3(float A, float cos_beta, float r_p) const override {
    return gtso3DLookup(volume(0, volume3_), size3_, A, cos_beta, r_p, layout3_);
  }
  float s4(float A, float cos_beta, float r_p, float cos_theta_o) const override {
    return gtso4DLookup(volume(1, volume4_), size4_, A, cos_beta, r_p, cos_theta_o, layout4_);
  }

 private:
  void load(const GtsoTable& t, const std::vector<std::uint8_t>* bytes, int k) {
    switch (format_) {
      case GtsoTexelFormat::kFloat32:
        floats_[k] = t.values;
        break;
      case GtsoTexelFormat::kBc4:
        blocks_[k].assign(bytes->size() / kBc4BlockBytes, 0);
        for (std::size_t b = 0; b < blocks_[k].size(); ++b) {
          for (int i = 0; i < kBc4BlockBytes; ++i) {
            blocks_[k][b] |= static_cast<std::uint64_t>((*bytes)[kBc4BlockBytes * b + i])
                             << (8 * i);
          }
        }
        break;
      case GtsoTexelFormat::kR16:
        r16_[k].resize(bytes->size() / 2);
        for (std::size_t i = 0; i < r16_[k].size(); ++i) {
          r16_[k][i] = static_cast<std::uint16_t>((*bytes)[2 * i] | (*bytes)[2 * i + 1] << 8);
        }
        break;
      case GtsoTexelFormat::kR8:
        r8_[k] = *bytes;
        break;
    }
  }
  GtsoVolume volume(int k, const int* v) const {
    const void* texels = nullptr;
    switch (format_) {
      case GtsoTexelFormat::kFloat32:
        texels = floats_[k].data();
        break;
      case GtsoTexelFormat::kBc4:
        texels = blocks_[k].data();
        break;
      case GtsoTexelFormat::kR16:
        texels = r16_[k].data();
        break;
      case GtsoTexelFormat::kR8:
        texels = r8_[k].data();
        break;
    }
    return GtsoVolume{format_, texels, v[0], v[1], v[2]};
  }

  GtsoTexelFormat format_;
  GtsoLayout layout3_, layout4_;
  int size3_[3] = {0, 0, 0};
  int size4_[4] = {0, 0, 0, 0};
  int volume3_[3] = {0, 0, 0};
  int volume4_[3] = {0, 0, 0};
  std::vector<std::uint64_t> blocks_[2];  // [3D, 4D]
  std::vector<std::uint16_t> r16_[2];
  std::vector<std::uint8_t> r8_[2];
  std::vector<float> floats_[2];
};

std::uint32_t le32(const std::string& bytes, std::size_t offset) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) {
    v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[offset + i])) << (8 * i);
  }
  return v;
}

// A DDS volume file as makeDds writes it (magic, DDS_HEADER, DX10 header, payload).
struct DdsFormat {
  std::uint32_t dxgi;  // DXGI_FORMAT_BC4_UNORM 80, R16_UNORM 56, R8_UNORM 61
  const char* name;
  std::size_t payload;  // bytes of the volume's payload
};
DdsFormat ddsFormat(VolumeFormat format, const std::array<int, 3>& v) {
  const std::size_t texels = static_cast<std::size_t>(v[0]) * v[1] * v[2];
  switch (format) {
    case VolumeFormat::kBc4:
      return {80, "BC4_UNORM", texels / 16 * kBc4BlockBytes};
    case VolumeFormat::kR16:
      return {56, "R16_UNORM", texels * 2};
    case VolumeFormat::kR8:
      break;
  }
  return {61, "R8_UNORM", texels};
}

// The payload of a volume DDS, checked against the format and extent of the gtso tables.
std::vector<std::uint8_t> readDdsPayload(const fs::path& path, const std::array<int, 3>& volume,
                                         VolumeFormat format) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  constexpr std::size_t kHeader = 4 + 124 + 20;  // "DDS ", DDS_HEADER, DDS_HEADER_DXT10
  const DdsFormat f = ddsFormat(format, volume);
  if (bytes.size() != kHeader + f.payload || bytes.compare(0, 4, "DDS ") != 0 ||
      le32(bytes, 128) != f.dxgi || le32(bytes, 12) != static_cast<std::uint32_t>(volume[1]) ||
      le32(bytes, 16) != static_cast<std::uint32_t>(volume[0]) ||
      le32(bytes, 24) != static_cast<std::uint32_t>(volume[2])) {
    throw Error(path.string() + ": not the " + f.name + " volume of the gtso tables (" +
                std::to_string(volume[0]) + "x" + std::to_string(volume[1]) + "x" +
                std::to_string(volume[2]) + "); rerun gtbake export");
  }
  return std::vector<std::uint8_t>(bytes.begin() + kHeader, bytes.end());
}

// A layout from export.json's "layouts": {"3d": {"chosen": {"axis": [x, y, z]}}, ...}.
GtsoLayout exportedLayout(const fs::path& file, const char* table) {
  if (!fs::exists(file)) return kGtsoIdentityLayout;  // luts/ from before the layout choice
  try {
    const nlohmann::json j = nlohmann::json::parse(readFile(file));
    const auto& axis = j.at("layouts").at(table).at("chosen").at("axis");
    GtsoLayout l{{axis.at(0).get<int>(), axis.at(1).get<int>(), axis.at(2).get<int>()}};
    int seen = 0;
    for (int k : l.axis) seen |= (k >= 0 && k < 3) ? 1 << k : 8;
    if (seen != 7) throw Error("not a permutation of the table axes");
    return l;
  } catch (const std::exception& e) {
    throw Error(file.string() + ": no valid layouts/" + table + "/chosen/axis (" + e.what() + ")");
  }
}

}  // namespace

TablesLookups makeTablesLookups(const fs::path& luts, bool encode_bc4, bool progress,
                                const GtsoLayouts* given) {
  const GtsoInput gtso = readGtsoInput(luts / "gtso");
  TablesLookups out;
  const fs::path dds[2] = {luts / "gtso3d.dds", luts / "gtso4d.dds"};
  const bool from_files = !encode_bc4 && fs::exists(dds[0]) && fs::exists(dds[1]);
  // The layouts of the volumes: export.json's for its files, else the export's choice.
  std::unique_ptr<GtsoLayouts> chosen;
  if (!from_files && !given) {
    chosen = std::make_unique<GtsoLayouts>(
        chooseLayouts(gtso, kLayoutLobes, nullptr, nullptr, progress));
    given = chosen.get();
  }
  const GtsoLayout layout3 =
      from_files ? exportedLayout(luts / "export.json", "3d") : given->t3.layout;
  const GtsoLayout layout4 =
      from_files ? exportedLayout(luts / "export.json", "4d") : given->t4.layout;
  out.info.layout_3d = layoutSwizzle(layout3);
  out.info.layout_4d = layoutSwizzle(layout4);
  // The two volumes of one format: the DDS files when present (and not encode_bc4), else made as
  // export makes them (the chosen layouts' BC4 blocks, their texels quantised).
  auto volumes = [&](VolumeFormat format, const char* suffix, std::string* source) {
    const fs::path dds3 = luts / ("gtso3d" + std::string(suffix) + ".dds");
    const fs::path dds4 = luts / ("gtso4d" + std::string(suffix) + ".dds");
    std::pair<std::vector<std::uint8_t>, std::vector<std::uint8_t>> v;
    if (from_files && fs::exists(dds3) && fs::exists(dds4)) {
      v.first = readDdsPayload(dds3, layoutVolume(gtso.table3d, layout3), format);
      v.second = readDdsPayload(dds4, layoutVolume(gtso.table4d, layout4), format);
      *source = dds3.filename().string() + ", " + dds4.filename().string();
      return v;
    }
    // Older luts/ without R16/R8 files: the texels export would write, in the files' layout.
    if (format == VolumeFormat::kBc4) {
      v.first = given->t3.bc4.bytes;
      v.second = given->t4.bc4.bytes;
      *source = "gtso/gtso3d.f32, gtso4d.f32 encoded by the export's BC4 encoder in its layouts";
    } else {
      const std::vector<float> f3 = permuteToLayout(gtso.table3d, layout3);
      const std::vector<float> f4 = permuteToLayout(gtso.table4d, layout4);
      v.first = quantizeUnorm(f3.data(), f3.size(), format);
      v.second = quantizeUnorm(f4.data(), f4.size(), format);
      *source = "gtso/gtso3d.f32, gtso4d.f32 quantised by the export's quantizeUnorm";
    }
    return v;
  };
  const auto bc4 = volumes(VolumeFormat::kBc4, "", &out.info.bc4_source);
  const auto r16 = volumes(VolumeFormat::kR16, "_r16", &out.info.r16_source);
  const auto r8 = volumes(VolumeFormat::kR8, "_r8", &out.info.r8_source);
  out.bc4 = std::make_unique<RuntimeTables>(GtsoTexelFormat::kBc4, gtso.table3d, gtso.table4d,
                                            &bc4.first, &bc4.second, layout3, layout4);
  out.r16 = std::make_unique<RuntimeTables>(GtsoTexelFormat::kR16, gtso.table3d, gtso.table4d,
                                            &r16.first, &r16.second, layout3, layout4);
  out.r8 = std::make_unique<RuntimeTables>(GtsoTexelFormat::kR8, gtso.table3d, gtso.table4d,
                                           &r8.first, &r8.second, layout3, layout4);
  out.floats =
      std::make_unique<RuntimeTables>(GtsoTexelFormat::kFloat32, gtso.table3d, gtso.table4d,
                                      nullptr, nullptr, kGtsoIdentityLayout, kGtsoIdentityLayout);
  out.info.u_table_fit = gtso.u;
  for (double k : gtso.s3_closed_form) out.info.s3_closed_form.push_back(static_cast<float>(k));
  return out;
}

}  // namespace gtbake
