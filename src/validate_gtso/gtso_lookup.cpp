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

namespace gtbake {

namespace {

namespace fs = std::filesystem;

// One volume texture (x fastest) whose texels are floats or BC4 blocks.
struct Volume {
  int size[3] = {0, 0, 0};
  std::vector<float> texels;  // decoded once: BC4 decode is exact per texel, so decoding at
                              // load gives the bits a per-fetch decode gives
  float fetch(int x, int y, int z) const {
    return texels[(static_cast<std::size_t>(z) * size[1] + y) * size[0] + x];
  }
};

struct AxisMap {
  std::string quantity;
  float min = 0.0f;
  float max = 1.0f;
  int n = 32;
};

float saturate(float x) {
  return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x);
}

// The axis quantity from the lookup inputs, as the header's quantityExpression.
float quantity(const std::string& q, float A, float cos_beta, float r_p, float cos_theta_o) {
  if (q == "A") return A;
  if (q == "cos_alpha_v") return std::sqrt(std::fmax(1.0f - A, 0.0f));
  if (q == "alpha_v") return std::acos(std::sqrt(std::fmax(1.0f - A, 0.0f)));
  if (q == "cos_beta") return cos_beta;
  if (q == "beta") return std::acos(std::fmin(std::fmax(cos_beta, -1.0f), 1.0f));
  if (q == "r_p") return r_p;
  if (q == "alpha") return r_p * r_p;
  if (q == "cos_theta_o") return cos_theta_o;
  if (q == "theta_o") return std::acos(std::fmin(std::fmax(cos_theta_o, -1.0f), 1.0f));
  throw Error("gtso.json: unknown axis quantity '" + q + "'");
}

float axisT(const AxisMap& a, float q) {
  return saturate((q - a.min) / (a.max - a.min));
}

float remap(float t, int n) {
  return (t * static_cast<float>(n - 1) + 0.5f) / static_cast<float>(n);
}

// gtsoSampleTrilinear of the header: clamp-to-edge trilinear filtering at texture coordinates.
float sampleTrilinear(const Volume& v, const float coord[3]) {
  int i0[3];
  int i1[3];
  float fr[3];
  for (int a = 0; a < 3; ++a) {
    const float p = coord[a] * static_cast<float>(v.size[a]) - 0.5f;
    const float fl = std::floor(p);
    fr[a] = p - fl;
    const int i = static_cast<int>(fl);
    i0[a] = i < 0 ? 0 : (i > v.size[a] - 1 ? v.size[a] - 1 : i);
    i1[a] = i + 1 < 0 ? 0 : (i + 1 > v.size[a] - 1 ? v.size[a] - 1 : i + 1);
  }
  float result = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    const int x = corner & 1 ? i1[0] : i0[0];
    const int y = corner & 2 ? i1[1] : i0[1];
    const int z = corner & 4 ? i1[2] : i0[2];
    const float w = (corner & 1 ? fr[0] : 1.0f - fr[0]) * (corner & 2 ? fr[1] : 1.0f - fr[1]) *
                    (corner & 4 ? fr[2] : 1.0f - fr[2]);
    result += w * v.fetch(x, y, z);
  }
  return result;
}

class TableLookup final : public GtsoLookup {
 public:
  TableLookup(std::vector<AxisMap> axes3, Volume v3, std::vector<AxisMap> axes4, Volume v4)
      : axes3_(std::move(axes3)),
        v3_(std::move(v3)),
        axes4_(std::move(axes4)),
        v4_(std::move(v4)) {}

  float s3(float A, float cos_beta, float r_p) const override {
    float coord[3];
    for (int a = 0; a < 3; ++a) {
      const AxisMap& m = axes3_[a];
      coord[a] = remap(axisT(m, quantity(m.quantity, A, cos_beta, r_p, cos_beta)), m.n);
    }
    return sampleTrilinear(v3_, coord);
  }

  float s4(float A, float cos_beta, float r_p, float cos_theta_o) const override {
    const AxisMap& x = axes4_[0];
    const AxisMap& y = axes4_[1];
    const AxisMap& z = axes4_[2];
    const AxisMap& w = axes4_[3];
    const float sw =
        axisT(w, quantity(w.quantity, A, cos_beta, r_p, cos_theta_o)) * static_cast<float>(w.n - 1);
    int s0 = static_cast<int>(sw);
    if (s0 > w.n - 2) s0 = w.n - 2;
    const float tz = axisT(z, quantity(z.quantity, A, cos_beta, r_p, cos_theta_o));
    const float zin = tz * static_cast<float>(z.n - 1) + 0.5f;
    const float depth = static_cast<float>(v4_.size[2]);
    const float u = remap(axisT(x, quantity(x.quantity, A, cos_beta, r_p, cos_theta_o)), x.n);
    const float v = remap(axisT(y, quantity(y.quantity, A, cos_beta, r_p, cos_theta_o)), y.n);
    const float c0[3] = {u, v, (static_cast<float>(s0 * z.n) + zin) / depth};
    const float c1[3] = {u, v, (static_cast<float>((s0 + 1) * z.n) + zin) / depth};
    const float f0 = sampleTrilinear(v4_, c0);
    const float f1 = sampleTrilinear(v4_, c1);
    return f0 + (f1 - f0) * (sw - static_cast<float>(s0));
  }

 private:
  std::vector<AxisMap> axes3_;
  Volume v3_;
  std::vector<AxisMap> axes4_;
  Volume v4_;
};

std::vector<AxisMap> axisMaps(const GtsoTable& t) {
  std::vector<AxisMap> maps;
  for (std::size_t i = 0; i < t.axes.size(); ++i) {
    maps.push_back({t.axes[i].quantity, static_cast<float>(t.axes[i].min),
                    static_cast<float>(t.axes[i].max), t.dims[i]});
  }
  return maps;
}

Volume floatVolume(const GtsoTable& t) {
  Volume v;
  for (int a = 0; a < 3; ++a) v.size[a] = t.volume[a];
  v.texels = t.values;
  return v;
}

// BC4 blocks (texture memory order) -> decoded texels.
Volume bc4Volume(const GtsoTable& t, const std::vector<std::uint8_t>& blocks) {
  Volume v;
  for (int a = 0; a < 3; ++a) v.size[a] = t.volume[a];
  v.texels = decodeBc4Volume(blocks.data(), v.size[0], v.size[1], v.size[2]);
  return v;
}

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
  out.bc4 = std::make_unique<TableLookup>(axisMaps(gtso.table3d), bc4Volume(gtso.table3d, blocks3),
                                          axisMaps(gtso.table4d), bc4Volume(gtso.table4d, blocks4));
  out.floats = std::make_unique<TableLookup>(axisMaps(gtso.table3d), floatVolume(gtso.table3d),
                                             axisMaps(gtso.table4d), floatVolume(gtso.table4d));
  out.info.u_table_fit = gtso.u;
  return out;
}

}  // namespace gtbake
