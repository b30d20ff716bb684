#include "validate_gtso/gtso_lookup.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "common/output_layout.h"
#include "encode/bc4_layout.h"
#include "encode/shipped_volumes.h"
#include "gtso/gtso_set.h"
#include "runtime/gtso_runtime.h"
#include "texture/bc4_block.h"
#include "texture/texture_containers.h"

namespace gtbake {

namespace {

namespace fs = std::filesystem;

// One table behind the runtime-lookup API of src/runtime/gtso_runtime.h (the code the
// header and shader includes ship): its texels, decoded from one format to floats, and its sizes.
class RuntimeTables final : public GtsoLookup {
 public:
  // bytes3/bytes4: the volumes' payloads as export writes them (BC4 blocks, little-endian R16,
  // R8); unused for float32, which reads the tables' floats.
  // layout3/4: the volumes' texture layouts (float32 reads the tables in table order).
  RuntimeTables(TexelFormat format, const GtsoTable& t3, const GtsoTable& t4,
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
    load(t3, bytes3, 0, volume3_);
    load(t4, bytes4, 1, volume4_);
  }

  float s3(float A, float cos_beta, float r_p) const override {
    return gtso3DLookup(volume(0, volume3_), size3_, A, cos_beta, r_p, layout3_);
  }
  float s4(float A, float cos_beta, float r_p, float cos_theta_o) const override {
    return gtso4DLookup(volume(1, volume4_), size4_, A, cos_beta, r_p, cos_theta_o, layout4_);
  }
  GtsoAxisT<float> axes3(float A, float cos_beta, float r_p) const override {
    return gtso3DAxes(A, cos_beta, r_p, size3_);
  }
  GtsoAxisT<float> axes4(float A, float cos_beta, float r_p, float cos_theta_o) const override {
    return gtso4DAxes(A, cos_beta, r_p, cos_theta_o, size4_);
  }
  float s3At(const GtsoAxisT<float>& a) const override {
    return gtso3DLookupAt(volume(0, volume3_), size3_, a, layout3_);
  }
  float s4At(const GtsoAxisT<float>& a) const override {
    return gtso4DLookupAt(volume(1, volume4_), size4_, a, layout4_);
  }

 private:
  // The texels as floats in texture order, x fastest. BC4, R16 and R8 are decoded once here, each
  // texel by the runtime's own gtsoFetchTexel: a lookup then reads, through the float path of the
  // same filtering code, the very floats the runtime's fetch of that format returns (the same
  // bits, without decoding up to 16 texels again at every lookup).
  void load(const GtsoTable& t, const std::vector<std::uint8_t>* bytes, int k, const int* v) {
    std::vector<std::uint64_t> blocks;
    std::vector<std::uint16_t> r16;
    const void* texels = nullptr;
    switch (format_) {
      case TexelFormat::kFloat32:
        floats_[k] = t.values;
        return;
      case TexelFormat::kBc4:
        blocks = bc4BlockWords(*bytes);
        texels = blocks.data();
        break;
      case TexelFormat::kR16:
        r16 = r16Words(*bytes);
        texels = r16.data();
        break;
      case TexelFormat::kR8:
        texels = bytes->data();
        break;
    }
    const GtsoVolume encoded{format_, texels, v[0], v[1], v[2]};
    floats_[k].resize(static_cast<std::size_t>(v[0]) * v[1] * v[2]);
    std::size_t linear = 0;
    for (int z = 0; z < v[2]; ++z) {
      for (int y = 0; y < v[1]; ++y) {
        for (int x = 0; x < v[0]; ++x) floats_[k][linear++] = gtsoFetchTexel(encoded, x, y, z);
      }
    }
  }
  GtsoVolume volume(int k, const int* v) const {
    return GtsoVolume{TexelFormat::kFloat32, floats_[k].data(), v[0], v[1], v[2]};
  }

  TexelFormat format_;
  GtsoLayout layout3_, layout4_;
  int size3_[3] = {0, 0, 0};
  int size4_[4] = {0, 0, 0, 0};
  int volume3_[3] = {0, 0, 0};
  int volume4_[3] = {0, 0, 0};
  std::vector<float> floats_[2];  // [3D, 4D]
};

}  // namespace

TablesLookups makeTablesLookups(const fs::path& luts) {
  const GtsoInput gtso = readGtsoInput(luts / kGtsoDir);
  const ShippedVolumes v = readShippedVolumes(luts / kEncodeDir, gtso);
  TablesLookups out;
  const GtsoLayout layout3 = v.t3.layout, layout4 = v.t4.layout;
  out.info.layout_3d = layoutSwizzle(layout3);
  out.info.layout_4d = layoutSwizzle(layout4);
  out.info.bc4_source = "gtso3d.dds, gtso4d.dds";
  out.info.r16_source = "gtso3d_r16.dds, gtso4d_r16.dds";
  out.info.r8_source = "gtso3d_r8.dds, gtso4d_r8.dds";
  out.bc4 = std::make_unique<RuntimeTables>(TexelFormat::kBc4, gtso.table3d, gtso.table4d,
                                            &v.t3.bc4.bytes, &v.t4.bc4.bytes, layout3, layout4);
  out.r16 = std::make_unique<RuntimeTables>(TexelFormat::kR16, gtso.table3d, gtso.table4d,
                                            &v.t3.r16.bytes, &v.t4.r16.bytes, layout3, layout4);
  out.r8 = std::make_unique<RuntimeTables>(TexelFormat::kR8, gtso.table3d, gtso.table4d,
                                           &v.t3.r8.bytes, &v.t4.r8.bytes, layout3, layout4);
  out.floats =
      std::make_unique<RuntimeTables>(TexelFormat::kFloat32, gtso.table3d, gtso.table4d, nullptr,
                                      nullptr, kGtsoIdentityLayout, kGtsoIdentityLayout);
  out.info.u_table_fit = gtso.u;
  for (double k : gtso.s3_closed_form) out.info.s3_closed_form.push_back(static_cast<float>(k));
  return out;
}

}  // namespace gtbake
