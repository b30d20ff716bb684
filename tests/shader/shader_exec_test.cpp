// Executes the generated shader includes: gtbake_tables.glsl and gtbake_tables.hlsl are compiled to
// SPIR-V with glslangValidator and run as Vulkan compute shaders on Mesa's CPU device (lavapipe),
// evaluating the 3D and 4D lookups, the cone model, multi-bounce and the closed-form S3 at 4,096
// random points; the results are compared with the C++ lookup code the header ships
// (runtime/gtso_runtime.h) on the same texels. Tables: the export test fixture, exported by
// this test into a temporary directory twice, the 4D table packed as an atlas (2 x 2 tiles, one
// empty: export_fixture.h) and as the fold (`--4d-layout fold`); textures uploaded as BC4_UNORM
// (when the device samples 3D BC4) and R16_UNORM. A third check uploads an atlas whose tiles are
// constants and reads each of the 4D lookup's two fetches: the device's filter stays in its tile.
//
// Tolerances (per point, float32 on both sides):
// - lookups: |shader - C++| <= D (3 * 2^-9 + 1e-3) + 2e-6 (+ 1/255 for BC4), D = max - min of the
//   8 texels of the trilinear footprint (the worse of the two fetches in 4D). The device filters
//   with 8 bits of sub-texel precision (VkPhysicalDeviceLimits::subTexelPrecisionBits, checked),
//   so each of the three weights may be off by 2^-9, moving the result by up to 2^-9 D each; the
//   1e-3 D covers the texture coordinate (the shader's log-form asinh and the device's acos/atan
//   against libm). lavapipe decodes and filters BC4 in 8 bits: + 2/255.
// - closed-form S3: the function's change under the device's float errors of its intermediate
//   values (closedFormTolerance).
// - cone model: the device's sin/cos/acos are far less exact than libm (Vulkan only requires
//   2^-11 absolute for sin/cos), so the tolerance is the model's sensitivity to errors of 2^-11
//   in each angle and each acos argument (coneTolerance), plus 1e-4. Multi-bounce: 1e-5.
// - profile tables: both fixture tables through the includes' one lookup (the second at an offset
//   in its arrays) against a lookup written by hand, 2e-6.
#include <gtest/gtest.h>
#include <unistd.h>
#include <vulkan/vulkan.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "encode/encode_command.h"
#include "export/export_command.h"
#include "export_fixture.h"
#include "runtime/gtso_runtime.h"
#include "support/vulkan_compute.h"

namespace {

namespace fs = std::filesystem;
using gtbake::test::Vulkan;
constexpr int kPoints = 4096;
constexpr int kLocalSize = 64;
// Per unit of texel range in the footprint: three 8-bit filter weights off by 2^-9 each, plus the
// texture coordinate's transcendental error (see the file comment).
constexpr float kFilterTolerance = 3.0f / 512.0f + 1e-3f;
// lavapipe decodes BC4 blocks to UNORM8 and returns the filtered value as UNORM8 (every BC4
// result is a multiple of 1/255; a texel centre reads 191/255 where the D3D float decode gives
// 0.7507): up to 1/255 from the decode and 1/255 from the output.
constexpr float kBc4DecodeTolerance = 2.0f / 255.0f;

struct Input {
  float A, cosBeta, rp, cosThetaO;
};

// ---- the exported fixture ----
struct Exported {
  fs::path dir;
  gtbake::GtsoLayout l4{};       // the 4D layout with its tiles (encode.json)
  std::array<int, 3> volume4{};  // the 4D texture's extent
  std::string glsl, hlsl;
  std::vector<std::uint8_t> bc4[2], r16[2];  // payloads of gtso3d / gtso4d
  float coeffs[6] = {};
  float u = 0.0f;
  float closedForm[gtbake::kGtsoS3ClosedFormCoeffs] = {};  // gtso.json closed_form (fixture)
};

std::vector<std::uint8_t> ddsPayload(const fs::path& path) {
  const std::string bytes = gtbake::readFile(path);
  constexpr std::size_t kHeader = 4 + 124 + 20;  // magic, DDS_HEADER, DDS_HEADER_DXT10
  return std::vector<std::uint8_t>(bytes.begin() + kHeader, bytes.end());
}

Exported exportFixture(gtbake::Layout4D packing) {
  Exported e;
  e.dir = fs::temp_directory_path() / ("gtbake_shader_test_" + std::to_string(::getpid()) + "_" +
                                       gtbake::layout4DName(packing));
  fs::remove_all(e.dir);
  gtbake::test::writeFixture(e.dir);
  gtbake::EncodeOptions c;
  c.gtso = e.dir / "gtso";
  c.out = e.dir / "out";
  c.progress = false;
  c.force_layout_3d = gtbake::test::kFixtureLayout3D;  // permuted volumes (export_fixture.h)
  c.force_layout_4d = gtbake::test::kFixtureLayout4D;
  c.layout_lobes = 16;
  c.layout_4d = packing;
  c.atlas_max_extent = gtbake::test::kFixtureAtlasMaxExtent;
  gtbake::runEncode(c);
  const nlohmann::json j =
      nlohmann::json::parse(gtbake::readFile(e.dir / "out" / "encode.json"))["layouts"]["4d"];
  const auto& axis = j["chosen"]["axis"];
  e.l4 = {{axis[0].get<int>(), axis[1].get<int>(), axis[2].get<int>()},
          j["packing"]["tiles_x"].get<int>()};
  for (int k = 0; k < 3; ++k) e.volume4[k] = j["volume"][k].get<int>();
  for (int k = 0; k < 2; ++k) {  // both ship a profile table (export_fixture.h)
    gtbake::test::writeProfileFixture(e.dir / "profiles", gtbake::test::kFixtureProfiles[k], k);
  }
  gtbake::ExportOptions o;
  o.profiles = e.dir / "profiles";
  o.fit = e.dir / "fit.json";
  o.gtso = e.dir / "gtso";
  o.out = e.dir / "out";
  gtbake::runExport(o);
  e.glsl = gtbake::readFile(e.dir / "out" / "gtbake_tables.glsl");
  e.hlsl = gtbake::readFile(e.dir / "out" / "gtbake_tables.hlsl");
  const char* base[2] = {"gtso3d", "gtso4d"};
  for (int t = 0; t < 2; ++t) {
    e.bc4[t] = ddsPayload(e.dir / "out" / (std::string(base[t]) + ".dds"));
    e.r16[t] = ddsPayload(e.dir / "out" / (std::string(base[t]) + "_r16.dds"));
  }
  for (int i = 0; i < 6; ++i) e.coeffs[i] = static_cast<float>(gtbake::test::kFixtureCoeffs[i]);
  e.u = static_cast<float>(gtbake::test::kFixtureU);
  static_assert(std::size(gtbake::test::kFixtureS3ClosedForm) == gtbake::kGtsoS3ClosedFormCoeffs);
  for (int i = 0; i < gtbake::kGtsoS3ClosedFormCoeffs; ++i) {
    e.closedForm[i] = static_cast<float>(gtbake::test::kFixtureS3ClosedForm[i]);
  }
  return e;
}

// ---- shader sources and SPIR-V ----
const char* kGlslMain = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Inputs { vec4 inputs[]; };
layout(std430, binding = 1) writeonly buffer Outputs { vec4 outputs[]; };
layout(binding = 2) uniform sampler3D table3D;
layout(binding = 3) uniform sampler3D table4D;
void main() {
  uint i = gl_GlobalInvocationID.x;
  vec4 p = inputs[i];
  outputs[2 * i] = vec4(gtso3DSample(table3D, p.x, p.y, p.z),
                        gtso4DSample(table4D, p.x, p.y, p.z, p.w), gtsoConeModel(p.x, p.y, p.z),
                        multiBounce(p.x, p.w));
  outputs[2 * i + 1] = vec4(gtsoS3ClosedForm(p.x, p.y, p.z), multiBounceTable_hbao(p.x, p.w),
                            multiBounceTable_gtao_runtime(p.x, p.w), 0.0);
}
)";

const char* kHlslMain = R"(
[[vk::binding(0)]] StructuredBuffer<float4> inputs;
[[vk::binding(1)]] RWStructuredBuffer<float4> outputs;
[[vk::binding(2)]] Texture3D<float> table3D;
[[vk::binding(3)]] Texture3D<float> table4D;
[[vk::binding(4)]] SamplerState linearClamp;
[numthreads(64, 1, 1)] void main(uint3 id : SV_DispatchThreadID) {
  float4 p = inputs[id.x];
  outputs[2 * id.x] = float4(gtso3DSample(table3D, linearClamp, p.x, p.y, p.z),
                             gtso4DSample(table4D, linearClamp, p.x, p.y, p.z, p.w),
                             gtsoConeModel(p.x, p.y, p.z), multiBounce(p.x, p.w));
  outputs[2 * id.x + 1] =
      float4(gtsoS3ClosedForm(p.x, p.y, p.z), multiBounceTable_hbao(p.x, p.w),
             multiBounceTable_gtao_runtime(p.x, p.w), 0.0);
}
)";

// ---- the C++ side ----
struct Reference {
  float s3, s4, cone, mb, closedForm, table, table0;  // table: hbao's, table0: gtao-runtime's
  float spread3, spread4;  // D of the tolerance: texel range of the trilinear footprint(s)
};

// max - min of the 8 texels the trilinear filter reads at texel position p in the box of n
// texels from lo (gtsoSampleTexels).
float footprint(const gtbake::GtsoVolume& v, const float* p, const int* lo, const int* n) {
  int i0[3], i1[3];
  for (int a = 0; a < 3; ++a) {
    const int i = static_cast<int>(std::floor(p[a]));
    i0[a] = lo[a] + std::clamp(i, 0, n[a] - 1);
    i1[a] = lo[a] + std::clamp(i + 1, 0, n[a] - 1);
  }
  float mn = 1e30f, mx = -1e30f;
  for (int k = 0; k < 8; ++k) {
    const float t = gtbake::gtsoFetchTexel(v, k & 1 ? i1[0] : i0[0], k & 2 ? i1[1] : i0[1],
                                           k & 4 ? i1[2] : i0[2]);
    mn = std::min(mn, t);
    mx = std::max(mx, t);
  }
  return mx - mn;
}

// The fixture's 3D layout (export_fixture.h) and its volume's texture extent in it.
gtbake::GtsoLayout fixtureLayout(const std::vector<int>& axes) {
  return {{axes[0], axes[1], axes[2]}};
}
std::array<int, 3> volume3D() {
  const gtbake::GtsoLayout l = fixtureLayout(gtbake::test::kFixtureLayout3D);
  const int* n = gtbake::test::kFixture3D;
  return {n[l.axis[0]], n[l.axis[1]], n[l.axis[2]]};
}

// D of the 4D tolerance: the larger footprint of the lookup's two fetches (gtso4DLookup).
float spread4D(const gtbake::GtsoVolume& v, const gtbake::GtsoLayout& l, const Input& p) {
  using namespace gtbake;
  const int* n4 = test::kFixture4D;
  const GtsoAxisT<float> a = gtso4DAxes(p.A, p.cosBeta, p.rp, p.cosThetaO, n4);
  const float sw = a.t[3] * static_cast<float>(n4[3] - 1);
  const int s0 = std::min(static_cast<int>(sw), n4[3] - 2);
  int n[3], lo0[3], lo1[3];
  float pos[3];
  for (int k = 0; k < 3; ++k) {
    n[k] = n4[l.axis[k]];
    pos[k] = a.t[l.axis[k]] * static_cast<float>(n[k] - 1);
  }
  gtso4DTileOrigin(l, n, s0, lo0);
  gtso4DTileOrigin(l, n, s0 + 1, lo1);
  return std::max(footprint(v, pos, lo0, n), footprint(v, pos, lo1, n));
}

Reference reference(const Exported& e, gtbake::GtsoTexelFormat format, const Input& p) {
  using namespace gtbake;
  const int* n3 = test::kFixture3D;
  const int* n4 = test::kFixture4D;
  const GtsoLayout l3 = fixtureLayout(test::kFixtureLayout3D);
  const GtsoLayout& l4 = e.l4;
  const void* d3 = format == GtsoTexelFormat::kBc4 ? e.bc4[0].data() : e.r16[0].data();
  const void* d4 = format == GtsoTexelFormat::kBc4 ? e.bc4[1].data() : e.r16[1].data();
  const std::array<int, 3> e3 = volume3D(), e4 = e.volume4;
  const GtsoVolume v3{format, d3, e3[0], e3[1], e3[2]};
  const GtsoVolume v4{format, d4, e4[0], e4[1], e4[2]};
  Reference r;
  r.s3 = gtso3DLookup(v3, n3, p.A, p.cosBeta, p.rp, l3);
  r.s4 = gtso4DLookup(v4, n4, p.A, p.cosBeta, p.rp, p.cosThetaO, l4);
  r.cone = gtsoConeModel(e.u, p.A, p.cosBeta, p.rp);
  r.mb = gtsoMultiBounce(e.coeffs, e.coeffs + 2, e.coeffs + 4, p.A, p.cosThetaO);
  r.closedForm = gtsoS3ClosedForm(e.closedForm, p.A, p.cosBeta, p.rp);
  r.table = static_cast<float>(test::fixtureTableLookup(1, p.A, p.cosThetaO));
  r.table0 = static_cast<float>(test::fixtureTableLookup(0, p.A, p.cosThetaO));
  const GtsoAxisT<float> a3 = gtso3DAxes(p.A, p.cosBeta, p.rp, n3);
  float p3[3];
  int lo3[3] = {0, 0, 0}, ext3[3];
  for (int k = 0; k < 3; ++k) {
    ext3[k] = e3[k];
    p3[k] = gtsoTexelRemap(a3.t[l3.axis[k]], n3[l3.axis[k]]) * static_cast<float>(e3[k]) - 0.5f;
  }
  r.spread3 = footprint(v3, p3, lo3, ext3);
  r.spread4 = spread4D(v4, l4, p);
  return r;
}

std::vector<Input> randomInputs() {
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f), u11(-1.0f, 1.0f);
  std::vector<Input> in(kPoints);
  for (Input& p : in) p = {u01(rng), u11(rng), u01(rng), u01(rng)};
  // A few exact corners: texel centres at the axis ends and the mirror limit.
  in[0] = {0.0f, 1.0f, 0.0f, 1.0f};
  in[1] = {1.0f, 0.0f, 1.0f, 0.0f};
  in[2] = {0.5f, 0.7f, 0.0f, 0.7f};
  return in;
}

// Sensitivity of the cone model to the device's trigonometry: Vulkan requires only 2^-11 absolute
// error of sin/cos, so each angle (alpha_v, alpha_s, beta) and each of the three acos arguments of
// the lens formula is perturbed by +-2^-11 (central differences in float); tolerance = 1e-4 + the
// sum of the six largest changes of S.
float coneTolerance(const Input& p, float u) {
  using namespace gtbake;
  const float alpha = p.rp * p.rp;
  const float omc = gtsoOneMinusExp(0.5f * alpha * alpha * std::log(u));
  if (omc <= 0.0f) return 1e-4f;
  const float av = gtsoAlphaV(p.A), as = 2.0f * std::asin(std::sqrt(0.5f * omc));
  const float beta = gtsoAcos(p.cosBeta);
  const float h = std::ldexp(1.0f, -11);
  const float pi = static_cast<float>(kGtsoPi);
  // S with the three acos arguments of the partial-overlap case shifted by dx[k].
  auto S = [&](float a1, float a2, float b, const float* dx) {
    a1 = std::max(a1, 0.0f);
    float omega;
    if (b >= a1 + a2) {
      omega = 0.0f;
    } else if (b <= std::fabs(a1 - a2)) {
      omega = gtsoCapIntersection(a1, a2, b);
    } else {
      const float c1 = std::cos(a1), c2 = std::cos(a2), cd = std::cos(b);
      const float s1 = std::sin(a1), s2 = std::sin(a2), sd = std::sin(b);
      const float t0 = gtsoAcos((cd - c1 * c2) / (s1 * s2) + dx[0]);
      const float t1 = gtsoAcos((c2 - cd * c1) / (sd * s1) + dx[1]);
      const float t2 = gtsoAcos((c1 - cd * c2) / (sd * s2) + dx[2]);
      omega = std::max(0.0f, 2.0f * (pi - t0 - c1 * t1 - c2 * t2));
    }
    const float sh = std::sin(0.5f * a2);
    return sh > 0.0f ? gtsoClamp01(omega / (4.0f * pi * sh * sh)) : 0.0f;
  };
  const float zero[3] = {0.0f, 0.0f, 0.0f};
  const float s0 = S(av, as, beta, zero);
  float t = 1e-4f;
  auto add = [&](float plus, float minus) {
    t += std::max(std::fabs(plus - s0), std::fabs(minus - s0));
  };
  add(S(av + h, as, beta, zero), S(av - h, as, beta, zero));
  add(S(av, as + h, beta, zero), S(av, std::max(as - h, 0.5f * as), beta, zero));
  add(S(av, as, beta + h, zero), S(av, as, beta - h, zero));
  for (int k = 0; k < 3; ++k) {
    float up[3] = {0.0f, 0.0f, 0.0f}, down[3] = {0.0f, 0.0f, 0.0f};
    up[k] = h;
    down[k] = -h;
    add(S(av, as, beta, up), S(av, as, beta, down));
  }
  return t;
}

// Sensitivity of the closed-form S3 to the device's float arithmetic. The shader and the C++
// header evaluate the same float operations, but the device may contract multiply-adds, sum in
// another order and has looser exp/log (Vulkan: exp 3 + 2|x| ULP, log 3 ULP or 2^-21 absolute).
// These are bounded as errors of the function's intermediate values: each of the nine
// polynomials P_s off by 2^-19 of the sum of its terms' magnitudes (ten float products and sums,
// plus the exp that reads it), the median u_m and the log-odds u each off by
// 2^-20 (1 + |value|) (their log). Tolerance = 1e-4 + the sum of the function's largest changes
// under each shift (double precision, both signs). Near the mirror step for r_p -> 0 the slope in
// u reaches sin(2 theta_o)/(2e-4), and the tolerance grows with it: that is the function's
// conditioning (a float input there is uncertain by as much), not slack.
float closedFormTolerance(const Input& in, const float* kf) {
  using namespace gtbake;
  constexpr int kB = kGtsoS3ClosedFormBasis;
  double k[kGtsoS3ClosedFormCoeffs];
  for (int i = 0; i < kGtsoS3ClosedFormCoeffs; ++i) k[i] = kf[i];
  const double A = in.A, cb = in.cosBeta, rp = in.rp;
  if (!(A > 0.0) || !(A < 1.0)) return 1e-4f;  // exact 0 and 1 on both sides
  const double mu = gtsoClamp01(cb), r = gtsoClamp01(rp);
  const double alpha = r * r + kGtsoS3ClosedFormAlphaFloor;
  const double h = mu * std::sqrt(1.0 - mu * mu) / alpha;
  double b[kB];
  gtsoS3ClosedFormBasis(std::sqrt(mu), r, h / (1.0 + h), b);
  const double s0 = gtsoS3ClosedForm(k, A, cb, rp);
  double tol = 1e-4;
  auto change = [&](double* kk) { return std::fabs(gtsoS3ClosedForm(kk, A, cb, rp) - s0); };
  for (int s = 0; s < kGtsoS3ClosedFormSets; ++s) {
    double mag = 0.0;
    for (int i = 0; i < kB; ++i) mag += std::fabs(k[s * kB + i] * b[i]);
    const double eps = std::ldexp(mag, -19);
    double worst = 0.0;
    for (double sign : {-1.0, 1.0}) {
      k[s * kB] += sign * eps;  // basis term 0 is 1: shifts P_s by eps
      worst = std::max(worst, change(k));
      k[s * kB] -= sign * eps;
    }
    tol += worst;
  }
  // The median through P_c (u_m += alpha P_c), and u through A (du/dA = 1 / (2 A (1 - A))).
  const GtsoS3ClosedFormLobe<double> lobe = gtsoS3ClosedFormLobe(k, cb, rp);
  const double dm = std::ldexp(1.0 + std::fabs(lobe.median), -20);
  double worstM = 0.0, worstU = 0.0;
  const double u = 0.5 * std::log(A / (1.0 - A));
  const double du = std::ldexp(1.0 + std::fabs(u), -20);
  for (double sign : {-1.0, 1.0}) {
    k[2 * kB] += sign * dm / alpha;
    worstM = std::max(worstM, change(k));
    k[2 * kB] -= sign * dm / alpha;
    const double A2 = 1.0 / (1.0 + std::exp(-2.0 * (u + sign * du)));
    worstU = std::max(worstU, std::fabs(gtsoS3ClosedForm(k, A2, cb, rp) - s0));
  }
  return static_cast<float>(tol + worstM + worstU);
}

class ShaderExec : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    exported_[0] = new Exported(exportFixture(gtbake::Layout4D::kAtlas));
    exported_[1] = new Exported(exportFixture(gtbake::Layout4D::kFold));
  }
  static void TearDownTestSuite() {
    for (Exported*& e : exported_) {
      fs::remove_all(e->dir);
      delete e;
      e = nullptr;
    }
  }

  // Runs one language with textures of one format, the 4D table packed as `packing`, and
  // compares every output.
  void check(bool hlsl, gtbake::GtsoTexelFormat format, gtbake::Layout4D packing) {
    Vulkan vk;
    const Exported& e = *exported_[packing == gtbake::Layout4D::kAtlas ? 0 : 1];
    ASSERT_EQ(e.l4.tilesX, packing == gtbake::Layout4D::kAtlas ? 2 : 1);
    const VkFormat vkFormat =
        format == gtbake::GtsoTexelFormat::kBc4 ? VK_FORMAT_BC4_UNORM_BLOCK : VK_FORMAT_R16_UNORM;
    if (!vk.samples3D(vkFormat)) {
      ASSERT_NE(vkFormat, VK_FORMAT_R16_UNORM) << vk.deviceName << " cannot sample R16 volumes";
      GTEST_SKIP() << vk.deviceName << " does not sample 3D BC4 images (R16 is checked)";
    }
    EXPECT_GE(vk.subTexelBits, 8u) << "the tolerance assumes 8 sub-texel bits";
    const std::string source =
        hlsl ? e.hlsl + kHlslMain : std::string("#version 450\n") + e.glsl + kGlslMain;
    const std::vector<std::uint32_t> spirv =
        gtbake::test::compileShader(GTBAKE_GLSLANG, e.dir, source, hlsl);
    const std::vector<Input> in = randomInputs();
    const int inBuf =
        vk.buffer(in.size() * sizeof(Input), in.data(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    const int outBuf = vk.buffer(in.size() * 32, nullptr, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    const std::array<int, 3> n3 = volume3D(), n4 = e.volume4;  // texture extents
    const bool bc4 = format == gtbake::GtsoTexelFormat::kBc4;
    const int img3 = vk.image(vkFormat, n3[0], n3[1], n3[2], bc4 ? e.bc4[0] : e.r16[0]);
    const int img4 = vk.image(vkFormat, n4[0], n4[1], n4[2], bc4 ? e.bc4[1] : e.r16[1]);
    vk.run(spirv, inBuf, outBuf, img3, img4, hlsl, kPoints / kLocalSize);
    const std::vector<float> out = vk.read(outBuf);
    float worst[7] = {0, 0, 0, 0, 0, 0, 0}, worstRatio = 0.0f;
    int failures = 0;
    for (int i = 0; i < kPoints; ++i) {
      const Reference r = reference(e, format, in[i]);
      const float got[7] = {out[8 * i],     out[8 * i + 1], out[8 * i + 2], out[8 * i + 3],
                            out[8 * i + 4], out[8 * i + 5], out[8 * i + 6]};
      const float want[7] = {r.s3, r.s4, r.cone, r.mb, r.closedForm, r.table, r.table0};
      const float decode = bc4 ? kBc4DecodeTolerance : 0.0f;
      const float tol[7] = {r.spread3 * kFilterTolerance + decode + 2e-6f,
                            r.spread4 * kFilterTolerance + decode + 2e-6f,
                            coneTolerance(in[i], e.u),
                            1e-5f,
                            closedFormTolerance(in[i], e.closedForm),
                            2e-6f,
                            2e-6f};
      for (int k = 0; k < 7; ++k) {
        const float d = std::fabs(got[k] - want[k]);
        worst[k] = std::max(worst[k], d);
        worstRatio = std::max(worstRatio, d / tol[k]);
        if (!(d <= tol[k]) && failures++ < 10) {
          ADD_FAILURE() << (hlsl ? "HLSL" : "GLSL") << " output " << k << " at A " << in[i].A
                        << " cosBeta " << in[i].cosBeta << " rp " << in[i].rp << " cosThetaO "
                        << in[i].cosThetaO << ": shader " << got[k] << ", C++ " << want[k]
                        << ", tolerance " << tol[k];
        }
      }
    }
    std::printf(
        "%s on %s, %s textures, 4D %s %dx%dx%d, %d points: max |shader - C++| S3 %.2e S4 %.2e "
        "cone %.2e multi-bounce %.2e closed-form S3 %.2e profile tables %.2e %.2e; worst error / "
        "tolerance "
        "%.3f\n",
        hlsl ? "HLSL" : "GLSL", vk.deviceName.c_str(), bc4 ? "BC4" : "R16",
        gtbake::layout4DName(packing), n4[0], n4[1], n4[2], kPoints, worst[0], worst[1], worst[2],
        worst[3], worst[4], worst[5], worst[6], worstRatio);
    EXPECT_EQ(failures, 0);
  }

  void checkTiles(bool hlsl);

  static Exported* exported_[2];  // the 4D table as an atlas, as the fold
};
Exported* ShaderExec::exported_[2] = {nullptr, nullptr};

// The 4D lookup's two fetches on their own (gtso4DAxisTexels, gtso4DTileCoord of the include):
// the slice s0, the fetch in its tile and in the next slice's, and gtso4DSample.
const char* kGlslTiles = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Inputs { vec4 inputs[]; };
layout(std430, binding = 1) writeonly buffer Outputs { vec4 outputs[]; };
layout(binding = 2) uniform sampler3D table3D;
layout(binding = 3) uniform sampler3D table4D;
void main() {
  uint i = gl_GlobalInvocationID.x;
  vec4 p = inputs[i];
  vec4 a = gtso4DAxisTexels(p.x, p.y, p.z, p.w);
  float s0 = min(floor(a.w), kGtso4DSize.w - 2.0);
  vec3 q = GTSO_4D_LAYOUT(a.xyz);
  outputs[2 * i] = vec4(s0, textureLod(table4D, gtso4DTileCoord(q, s0), 0.0).r,
                        textureLod(table4D, gtso4DTileCoord(q, s0 + 1.0), 0.0).r,
                        gtso4DSample(table4D, p.x, p.y, p.z, p.w));
  outputs[2 * i + 1] = vec4(0.0);
}
)";
const char* kHlslTiles = R"(
[[vk::binding(0)]] StructuredBuffer<float4> inputs;
[[vk::binding(1)]] RWStructuredBuffer<float4> outputs;
[[vk::binding(2)]] Texture3D<float> table3D;
[[vk::binding(3)]] Texture3D<float> table4D;
[[vk::binding(4)]] SamplerState linearClamp;
[numthreads(64, 1, 1)] void main(uint3 id : SV_DispatchThreadID) {
  float4 p = inputs[id.x];
  float4 a = gtso4DAxisTexels(p.x, p.y, p.z, p.w);
  float s0 = min(floor(a.w), kGtso4DSize.w - 2.0);
  float3 q = GTSO_4D_LAYOUT(a.xyz);
  outputs[2 * id.x] = float4(s0, table4D.SampleLevel(linearClamp, gtso4DTileCoord(q, s0), 0.0),
                             table4D.SampleLevel(linearClamp, gtso4DTileCoord(q, s0 + 1.0), 0.0),
                             gtso4DSample(table4D, linearClamp, p.x, p.y, p.z, p.w));
  outputs[2 * id.x + 1] = float4(0.0, 0.0, 0.0, 0.0);
}
)";

// The device's filter never reads another tile: the exported atlas's include samples an R16
// atlas whose tile w holds the constant (w + 1) 4096 / 65535 (the empty tile 1), at the random
// inputs and every combination of the axis ends (coordinates on the tiles' edge texel centres).
// Each fetch must return its tile's constant; a weight of 2^-8 (the device's sub-texel step) on
// a neighbouring tile would move it by >= 4096 / 65535 / 256 = 2.4e-4.
void ShaderExec::checkTiles(bool hlsl) {
  Vulkan vk;
  const Exported& e = *exported_[0];
  const int* n4 = gtbake::test::kFixture4D;
  const int n[3] = {n4[e.l4.axis[0]], n4[e.l4.axis[1]], n4[e.l4.axis[2]]};
  const std::array<int, 3>& v = e.volume4;
  auto constant = [&](int w) { return w < n4[3] ? (w + 1) * 4096 : 65535; };
  std::vector<std::uint8_t> texels;
  for (int z = 0; z < v[2]; ++z)
    for (int y = 0; y < v[1]; ++y)
      for (int x = 0; x < v[0]; ++x) {
        const int w = z / n[2] * e.l4.tilesX + x / n[0];
        texels.push_back(static_cast<std::uint8_t>(constant(w) & 0xFF));
        texels.push_back(static_cast<std::uint8_t>(constant(w) >> 8));
      }
  std::vector<Input> in = randomInputs();
  int at = 3;
  for (float A : {0.0f, 1.0f})
    for (float cb : {-1.0f, 0.0f, 1.0f})
      for (float rp : {0.0f, 1.0f})
        for (float co : {0.0f, 1.0f}) in[at++] = {A, cb, rp, co};
  const std::string source =
      hlsl ? e.hlsl + kHlslTiles : std::string("#version 450\n") + e.glsl + kGlslTiles;
  const std::vector<std::uint32_t> spirv =
      gtbake::test::compileShader(GTBAKE_GLSLANG, e.dir, source, hlsl);
  const int inBuf =
      vk.buffer(in.size() * sizeof(Input), in.data(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  const int outBuf = vk.buffer(in.size() * 32, nullptr, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  const int img = vk.image(VK_FORMAT_R16_UNORM, v[0], v[1], v[2], texels);
  vk.run(spirv, inBuf, outBuf, img, img, hlsl, kPoints / kLocalSize);
  const std::vector<float> out = vk.read(outBuf);
  float worst = 0.0f;
  for (int i = 0; i < kPoints; ++i) {
    const int s0 = static_cast<int>(out[8 * i]);
    ASSERT_TRUE(s0 >= 0 && s0 <= n4[3] - 2 && out[8 * i] == static_cast<float>(s0)) << i;
    const float c0 = constant(s0) / 65535.0f, c1 = constant(s0 + 1) / 65535.0f;
    const float lerp = out[8 * i + 3];
    worst = std::max({worst, std::fabs(out[8 * i + 1] - c0), std::fabs(out[8 * i + 2] - c1),
                      std::max(0.0f, std::min(c0, c1) - lerp), std::max(0.0f, lerp - c1)});
  }
  std::printf("%s on %s, 4D atlas of constant tiles: max |fetch - its tile's constant| %.2e\n",
              hlsl ? "HLSL" : "GLSL", vk.deviceName.c_str(), worst);
  EXPECT_LE(worst, 2e-6f);
}

TEST_F(ShaderExec, GlslR16) {
  check(false, gtbake::GtsoTexelFormat::kR16, gtbake::Layout4D::kAtlas);
}
TEST_F(ShaderExec, HlslR16) {
  check(true, gtbake::GtsoTexelFormat::kR16, gtbake::Layout4D::kAtlas);
}
TEST_F(ShaderExec, GlslBc4) {
  check(false, gtbake::GtsoTexelFormat::kBc4, gtbake::Layout4D::kAtlas);
}
TEST_F(ShaderExec, HlslBc4) {
  check(true, gtbake::GtsoTexelFormat::kBc4, gtbake::Layout4D::kAtlas);
}
TEST_F(ShaderExec, GlslR16Fold) {
  check(false, gtbake::GtsoTexelFormat::kR16, gtbake::Layout4D::kFold);
}
TEST_F(ShaderExec, HlslR16Fold) {
  check(true, gtbake::GtsoTexelFormat::kR16, gtbake::Layout4D::kFold);
}
TEST_F(ShaderExec, GlslBc4Fold) {
  check(false, gtbake::GtsoTexelFormat::kBc4, gtbake::Layout4D::kFold);
}
TEST_F(ShaderExec, HlslBc4Fold) {
  check(true, gtbake::GtsoTexelFormat::kBc4, gtbake::Layout4D::kFold);
}
TEST_F(ShaderExec, GlslFetchesStayInTheirAtlasTiles) {
  checkTiles(false);
}
TEST_F(ShaderExec, HlslFetchesStayInTheirAtlasTiles) {
  checkTiles(true);
}

}  // namespace
