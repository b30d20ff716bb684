// `gtbake export` end to end on the synthetic fixture: the DDS and KTX2 files parsed back with an
// independent reader, the reported BC4 errors recomputed from the files, input validation, float
// literals, and the generated header and shader includes compiled on their own.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <tuple>

#include "common/error.h"
#include "common/output_set.h"
#include "encode/bc4_layout.h"
#include "encode/encode_command.h"
#include "export/export_command.h"
#include "export/generated_code.h"
#include "export_fixture.h"
#include "texture/bc4_block.h"
#include "texture/bc4_encoder.h"
#include "texture/texture_containers.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::uint64_t le(const std::string& s, std::size_t at, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i)
    v |= std::uint64_t(static_cast<unsigned char>(s[at + i])) << 8 * i;
  return v;
}

class ExportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() /
        ("gtbake_export_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    test::writeFixture(dir_);
    options_.fit = dir_ / "fit.json";
    options_.gtso = dir_ / "gtso";
    options_.out = dir_ / "out";
    options_.command_line = "gtbake export (test)";
    encode_.gtso = options_.gtso;
    encode_.out = options_.out;
    encode_.progress = false;
    // Byte-level checks against the table order; the layout choice has its own tests below.
    encode_.force_layout_3d = {0, 1, 2};
    encode_.force_layout_4d = {0, 1, 2};
    encode_.layout_lobes = 16;
  }
  // gtso -> encode -> export, as `gtbake all` runs them.
  ExportResult exportAll() {
    runEncode(encode_);
    return runExport(options_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  void expectErrorAndNoOutput(const std::string& fragment) {
    try {
      exportAll();
      FAIL() << "expected gtbake::Error containing \"" << fragment << "\"";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(fragment), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
    }
    EXPECT_FALSE(fs::exists(options_.out / "gtbake_tables.h"));
  }

  fs::path dir_;
  EncodeOptions encode_;
  ExportOptions options_;
};

// The 4D payload decoded back must reproduce the reported RMSE and max error.
void checkPayloadErrors(const std::string& payload, const std::vector<float>& table, int w, int h,
                        int d, double rmse, double max_abs) {
  ASSERT_EQ(payload.size(), std::size_t(w / 4) * (h / 4) * d * 8);
  double sse = 0.0, worst = 0.0;
  for (int z = 0; z < d; ++z)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t b = (std::size_t(z) * (h / 4) + y / 4) * (w / 4) + x / 4;
        const auto texels = decodeBc4Block(reinterpret_cast<const std::uint8_t*>(&payload[8 * b]));
        const double diff = texels[(y % 4) * 4 + x % 4] - double(table[(z * h + y) * w + x]);
        sse += diff * diff;
        worst = std::fmax(worst, std::fabs(diff));
      }
  EXPECT_NEAR(std::sqrt(sse / table.size()), rmse, 1e-12);
  EXPECT_EQ(worst, max_abs);
}

TEST_F(ExportTest, DdsFieldsAndPayload) {
  const ExportResult r = exportAll();
  const std::string s = slurp(options_.out / "gtso4d.dds");
  const int w = 8, h = 8, d = 12;
  ASSERT_EQ(s.size(), 4 + 124 + 20 + std::size_t(w / 4 * h / 4 * d * 8));
  EXPECT_EQ(s.substr(0, 4), "DDS ");
  EXPECT_EQ(le(s, 4, 4), 124u);                                            // dwSize
  EXPECT_EQ(le(s, 8, 4), 0x1u | 0x2 | 0x4 | 0x1000 | 0x80000 | 0x800000);  // dwFlags
  EXPECT_EQ(le(s, 12, 4), std::uint64_t(h));
  EXPECT_EQ(le(s, 16, 4), std::uint64_t(w));
  EXPECT_EQ(le(s, 20, 4), std::uint64_t(w / 4 * h / 4 * 8));  // one slice of blocks
  EXPECT_EQ(le(s, 24, 4), std::uint64_t(d));
  EXPECT_EQ(le(s, 28, 4), 1u);  // mips
  for (int i = 0; i < 11; ++i) EXPECT_EQ(le(s, 32 + 4 * i, 4), 0u);
  EXPECT_EQ(le(s, 76, 4), 32u);   // pixel format size
  EXPECT_EQ(le(s, 80, 4), 0x4u);  // DDPF_FOURCC
  EXPECT_EQ(s.substr(84, 4), "DX10");
  for (int i = 0; i < 5; ++i) EXPECT_EQ(le(s, 88 + 4 * i, 4), 0u);
  EXPECT_EQ(le(s, 108, 4), 0x1000u | 0x8);  // TEXTURE | COMPLEX
  EXPECT_EQ(le(s, 112, 4), 0x200000u);      // VOLUME
  for (int i = 0; i < 3; ++i) EXPECT_EQ(le(s, 116 + 4 * i, 4), 0u);
  EXPECT_EQ(le(s, 128, 4), 80u);  // DXGI_FORMAT_BC4_UNORM
  EXPECT_EQ(le(s, 132, 4), 4u);   // TEXTURE3D
  EXPECT_EQ(le(s, 136, 4), 0u);
  EXPECT_EQ(le(s, 140, 4), 1u);  // arraySize
  EXPECT_EQ(le(s, 144, 4), 0u);
  checkPayloadErrors(s.substr(148), test::fixtureTable4D(), w, h, d, r.bc4_rmse_4d, r.bc4_max_4d);
  // Byte for byte: the payload is the encoder's output for the folded float table.
  const std::vector<float> t4 = test::fixtureTable4D();
  const Bc4Volume v = encodeBc4Volume(Bc4Encoder(), t4.data(), w, h, d, nullptr);
  EXPECT_EQ(s.substr(148), std::string(v.bytes.begin(), v.bytes.end()));
  const std::string s3 = slurp(options_.out / "gtso3d.dds");
  checkPayloadErrors(s3.substr(148), test::fixtureTable3D(), 8, 8, 6, r.bc4_rmse_3d, r.bc4_max_3d);
}

// Unforced, encode chooses each table's layout with the encoder, records every candidate and the
// choice in encode.json by the stated rule, writes every format of the table in that layout and
// generates code that reads it.
TEST_F(ExportTest, ChosenLayoutIsWrittenRecordedAndRead) {
  encode_.force_layout_3d.clear();
  encode_.force_layout_4d.clear();
  encode_.atlas_max_extent = test::kFixtureAtlasMaxExtent;  // the 4D volume tiled in an atlas
  exportAll();
  const nlohmann::json j = nlohmann::json::parse(slurp(options_.out / "encode.json"));
  const GtsoInput in = readGtsoInput(options_.gtso);
  const std::string header = slurp(options_.out / "gtbake_tables.h");
  const std::string glsl = slurp(options_.out / "gtbake_tables.glsl");
  for (const auto& [key, table] : {std::pair{"3d", &in.table3d}, std::pair{"4d", &in.table4d}}) {
    const auto& c = j["layouts"][key];
    // 3D: the fixture's 6 r_p texels must stay on z (2 of 6 permutations); 4D: 3 block planes.
    ASSERT_EQ(c["candidates"].size(), std::string(key) == "3d" ? 2u : 3u) << key;
    double lowest = 1e30;
    for (const auto& k : c["candidates"])
      lowest = std::min(lowest, k["uniform"]["rms"].get<double>());
    int chosen = 0;
    for (const auto& k : c["candidates"]) {
      const double rms = k["uniform"]["rms"];
      if (k["chosen"].get<bool>()) {
        ++chosen;
        EXPECT_LE(rms, lowest * (1.0 + kLayoutRmsTie)) << key;
        EXPECT_EQ(k["layout"]["axis"], c["chosen"]["axis"]);
      }
    }
    EXPECT_EQ(chosen, 1) << key;
    const auto& axis = c["chosen"]["axis"];
    const int tiles = std::string(key) == "4d" ? c["packing"]["tiles_x"].get<int>() : 1;
    const GtsoLayout l{{axis[0].get<int>(), axis[1].get<int>(), axis[2].get<int>()}, tiles};
    const std::vector<float> texels = permuteToLayout(*table, l);
    const std::array<int, 3> v = layoutVolume(*table, l);
    EXPECT_EQ(c["volume"], nlohmann::json(v)) << key;
    for (int e : v) EXPECT_LE(e, test::kFixtureAtlasMaxExtent) << key;
    const std::string dds = slurp(options_.out / (std::string("gtso") + key + ".dds"));
    const std::string ktx = slurp(options_.out / (std::string("gtso") + key + ".ktx2"));
    EXPECT_EQ(le(dds, 16, 4), std::uint64_t(v[0])) << "DDS dwWidth";
    EXPECT_EQ(le(dds, 12, 4), std::uint64_t(v[1])) << "DDS dwHeight";
    EXPECT_EQ(le(dds, 24, 4), std::uint64_t(v[2])) << "DDS dwDepth";
    EXPECT_EQ(le(ktx, 20, 4), std::uint64_t(v[0])) << "KTX2 pixelWidth";
    EXPECT_EQ(le(ktx, 24, 4), std::uint64_t(v[1])) << "KTX2 pixelHeight";
    EXPECT_EQ(le(ktx, 28, 4), std::uint64_t(v[2])) << "KTX2 pixelDepth";
    const std::string base = std::string("gtso") + key;
    const Bc4Volume bc4 = encodeBc4Volume(Bc4Encoder(), texels.data(), v[0], v[1], v[2], nullptr);
    EXPECT_EQ(slurp(options_.out / (base + ".dds")).substr(148),
              std::string(bc4.bytes.begin(), bc4.bytes.end()));
    const auto r16 = quantizeUnorm(texels.data(), texels.size(), TexelFormat::kR16);
    EXPECT_EQ(slurp(options_.out / (base + "_r16.dds")).substr(148),
              std::string(r16.begin(), r16.end()));
    const std::string name = std::string("kGtso") + (key[0] == '3' ? "3" : "4") + "DLayout";
    const std::string constant = "inline constexpr GtsoLayout " + name + " = {{" +
                                 std::to_string(l.axis[0]) + ", " + std::to_string(l.axis[1]) +
                                 ", " + std::to_string(l.axis[2]) + "}, " +
                                 std::to_string(l.tilesX) + "};";
    EXPECT_NE(header.find(constant), std::string::npos) << constant;
    const std::string macro = std::string("#define GTSO_") + (key[0] == '3' ? "3" : "4") +
                              "D_LAYOUT(c) (c)." + layoutSwizzle(l);
    EXPECT_NE(glsl.find(macro), std::string::npos) << macro;
  }
}

// R16_UNORM / R8_UNORM beside BC4: DX10 format, row pitch, KTX2 vkFormat, type size and DFD, and
// the payload = round(clamp(v) * (2^bits - 1)) of the float table, little-endian.
TEST_F(ExportTest, UnormVolumesFieldsAndPayload) {
  exportAll();
  const std::vector<float> t4 = test::fixtureTable4D();
  const int w = 8, h = 8, d = 12;
  for (const auto& [suffix, bytes, dxgi, vk] :
       {std::tuple{"_r16", 2, 56u, 70u}, std::tuple{"_r8", 1, 61u, 9u}}) {
    const std::string dds = slurp(options_.out / (std::string("gtso4d") + suffix + ".dds"));
    ASSERT_EQ(dds.size(), 148 + std::size_t(w) * h * d * bytes) << suffix;
    EXPECT_EQ(le(dds, 8, 4), 0x1u | 0x2 | 0x4 | 0x8 | 0x1000 | 0x800000);  // DDSD_PITCH
    EXPECT_EQ(le(dds, 20, 4), std::uint64_t(w * bytes));                   // row pitch
    EXPECT_EQ(le(dds, 128, 4), dxgi);
    const double scale = bytes == 2 ? 65535.0 : 255.0;
    for (std::size_t i = 0; i < t4.size(); ++i) {
      const double v = std::clamp(static_cast<double>(t4[i]), 0.0, 1.0);
      ASSERT_EQ(le(dds, 148 + i * bytes, bytes), std::uint64_t(std::lround(v * scale))) << i;
    }
    const std::string ktx = slurp(options_.out / (std::string("gtso4d") + suffix + ".ktx2"));
    EXPECT_EQ(le(ktx, 12, 4), vk);
    EXPECT_EQ(le(ktx, 16, 4), std::uint64_t(bytes));  // typeSize
    const std::size_t dfd = le(ktx, 48, 4);
    EXPECT_EQ(le(ktx, dfd + 12, 4) & 0xFF, 1u);  // KHR_DF_MODEL_RGBSDA
    EXPECT_EQ(le(ktx, dfd + 16, 4), 0u);         // texel block 1x1x1x1
    EXPECT_EQ(le(ktx, dfd + 20, 4), std::uint64_t(bytes));
    const std::size_t data = le(ktx, 80, 8);
    EXPECT_EQ(data % 4, 0u);
    EXPECT_EQ(ktx.substr(data), dds.substr(148));
  }
}

// encode.json end_to_end: every format of each table measured as shipped (docs/export.md §2b), on
// two fresh seeds; BC4 on the report seed is the layout choice's own report of the same blocks,
// R16 is float32 within its quantisation, and the recommendation follows its rule.
TEST_F(ExportTest, EncodedFormatsAreMeasuredAsShipped) {
  exportAll();
  const nlohmann::json e = nlohmann::json::parse(slurp(options_.out / "encode.json"));
  for (const auto& [key, n] :
       {std::pair{"3d", std::size_t{8 * 8 * 6}}, std::pair{"4d", std::size_t{8 * 8 * 12}}}) {
    const nlohmann::json& t = e["end_to_end"][key];
    const nlohmann::json& f = t["formats"];
    ASSERT_EQ(f.size(), 4u) << key;
    EXPECT_EQ(f["float32"]["bytes"].get<std::size_t>(), 4 * n);
    EXPECT_EQ(f["bc4"]["bytes"].get<std::size_t>(), n / 2);  // 8 bytes per 4x4 block
    EXPECT_EQ(f["r16"]["bytes"].get<std::size_t>(), 2 * n);
    EXPECT_EQ(f["r8"]["bytes"].get<std::size_t>(), n);
    EXPECT_EQ(f["float32"]["texel_max_error"].get<double>(), 0.0);
    EXPECT_LE(f["r16"]["texel_max_error"].get<double>(), 0.5 / 65535 + 1e-7);
    EXPECT_LE(f["r8"]["texel_max_error"].get<double>(), 0.5 / 255 + 1e-7);
    EXPECT_GT(f["r8"]["texel_max_error"].get<double>(), 0.25 / 255);  // not exact by accident
    for (const auto& [name, format] : f.items()) {
      const nlohmann::json& seeds = format["uniform"]["per_seed"];
      ASSERT_EQ(seeds.size(), 2u) << name;
      EXPECT_EQ(seeds[0]["seed"], 1002);
      EXPECT_EQ(seeds[1]["seed"], 1003);
      EXPECT_EQ(format["uniform"]["max"].get<double>(),
                std::max(seeds[0]["max"].get<double>(), seeds[1]["max"].get<double>()));
    }
    const nlohmann::json& layout = e["layouts"][key];
    EXPECT_EQ(f["bc4"]["uniform"]["per_seed"][0]["max"], layout["report_uniform_max"]);
    EXPECT_EQ(f["bc4"]["uniform"]["per_seed"][0]["rms"], layout["report_uniform_rms"]);
    EXPECT_NEAR(f["r16"]["uniform"]["rms"].get<double>(),
                f["float32"]["uniform"]["rms"].get<double>(), 1e-5);
    // The rule by hand: the smallest format within 1.5x float32 on uniform max, RMS, stress max.
    std::string best = "float32";
    for (const char* name : {"bc4", "r16", "r8"}) {
      auto within = [&](const char* set, const char* k) {
        return f[name][set][k].get<double>() <= 1.5 * f["float32"][set][k].get<double>();
      };
      if (within("uniform", "max") && within("uniform", "rms") && within("stress", "max") &&
          f[name]["bytes"].get<std::size_t>() < f[best]["bytes"].get<std::size_t>()) {
        best = name;
      }
    }
    EXPECT_EQ(t["recommended"], best) << key;
  }
}

TEST_F(ExportTest, Ktx2FieldsAndPayload) {
  const ExportResult r = exportAll();
  const std::string s = slurp(options_.out / "gtso3d.ktx2");
  const unsigned char id[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
  EXPECT_EQ(s.substr(0, 12), std::string(reinterpret_cast<const char*>(id), 12));
  EXPECT_EQ(le(s, 12, 4), 139u);  // VK_FORMAT_BC4_UNORM_BLOCK
  EXPECT_EQ(le(s, 16, 4), 1u);    // typeSize
  EXPECT_EQ(le(s, 20, 4), 8u);
  EXPECT_EQ(le(s, 24, 4), 8u);
  EXPECT_EQ(le(s, 28, 4), 6u);
  EXPECT_EQ(le(s, 32, 4), 0u);  // layerCount
  EXPECT_EQ(le(s, 36, 4), 1u);  // faceCount
  EXPECT_EQ(le(s, 40, 4), 1u);  // levelCount
  EXPECT_EQ(le(s, 44, 4), 0u);  // supercompression
  const std::uint64_t dfd = le(s, 48, 4), dfd_len = le(s, 52, 4);
  const std::uint64_t kvd = le(s, 56, 4), kvd_len = le(s, 60, 4);
  EXPECT_EQ(le(s, 64, 8), 0u);
  EXPECT_EQ(le(s, 72, 8), 0u);
  const std::uint64_t data = le(s, 80, 8), data_len = le(s, 88, 8);
  EXPECT_EQ(le(s, 96, 8), data_len);  // uncompressedByteLength
  EXPECT_EQ(dfd, 104u);
  EXPECT_EQ(dfd_len, 44u);
  EXPECT_EQ(le(s, dfd, 4), 44u);                 // dfdTotalSize
  EXPECT_EQ(le(s, dfd + 4, 4), 0u);              // vendor KHR, type basic
  EXPECT_EQ(le(s, dfd + 8, 4), 2u | 40u << 16);  // version 2, block size 40
  EXPECT_EQ(s[dfd + 12], char(131));             // KHR_DF_MODEL_BC4
  EXPECT_EQ(s[dfd + 13], 1);                     // BT709 primaries
  EXPECT_EQ(s[dfd + 14], 1);                     // linear transfer
  EXPECT_EQ(s[dfd + 15], 0);                     // flags
  EXPECT_EQ(le(s, dfd + 16, 4), 0x0303u);        // 4x4x1x1 block
  EXPECT_EQ(le(s, dfd + 20, 4), 8u);             // bytesPlane0
  EXPECT_EQ(le(s, dfd + 24, 4), 0u);
  EXPECT_EQ(le(s, dfd + 28, 2), 0u);  // bitOffset
  EXPECT_EQ(s[dfd + 30], 63);         // bitLength − 1
  EXPECT_EQ(s[dfd + 31], 0);          // channel BC4 data, unsigned, not linear
  EXPECT_EQ(le(s, dfd + 32, 4), 0u);
  EXPECT_EQ(le(s, dfd + 36, 4), 0u);
  EXPECT_EQ(le(s, dfd + 40, 4), 0xFFFFFFFFu);
  EXPECT_EQ(kvd, dfd + dfd_len);
  const std::string kv = std::string("KTXwriter") + '\0' + "gtbake ";
  EXPECT_EQ(s.substr(kvd + 4, kv.size()), kv);
  const std::uint64_t kv_len = le(s, kvd, 4);
  EXPECT_EQ(s[kvd + 4 + kv_len - 1], '\0');
  EXPECT_EQ(kvd_len, (4 + kv_len + 3) / 4 * 4);
  EXPECT_EQ(data % 8, 0u);
  EXPECT_GE(data, kvd + kvd_len);
  EXPECT_LT(data, kvd + kvd_len + 8);
  EXPECT_EQ(data + data_len, s.size());
  checkPayloadErrors(s.substr(data), test::fixtureTable3D(), 8, 8, 6, r.bc4_rmse_3d, r.bc4_max_3d);
  // Same blocks in both containers.
  EXPECT_EQ(s.substr(data), slurp(options_.out / "gtso3d.dds").substr(148));
}

TEST_F(ExportTest, DeterministicAcrossThreadCounts) {
  encode_.threads = 1;
  exportAll();
  const std::string one = slurp(options_.out / "gtbake_tables.h");
  encode_.threads = 2;
  exportAll();
  EXPECT_EQ(one, slurp(options_.out / "gtbake_tables.h"));
}

TEST_F(ExportTest, RejectsMissingFit) {
  fs::remove(dir_ / "fit.json");
  expectErrorAndNoOutput("fit.json");
}

TEST_F(ExportTest, RejectsWrongTableSize) {
  std::ofstream(dir_ / "gtso" / "gtso4d.f32", std::ios::binary) << "short";
  resealOutputSet(dir_ / "gtso", "gtso");  // past the manifest, to the reader's own check
  expectErrorAndNoOutput("gtso4d.f32");
}

TEST_F(ExportTest, RejectsAxesTheRuntimeDoesNotRead) {
  std::string json = slurp(dir_ / "gtso" / "gtso.json");
  json.replace(json.find("\"beta_lobe_split\""), 17, "\"cos_beta\"");
  std::ofstream(dir_ / "gtso" / "gtso.json") << json;
  resealOutputSet(dir_ / "gtso", "gtso");
  expectErrorAndNoOutput("the runtime lookup expects \"beta_lobe_split\"");
}

TEST_F(ExportTest, RejectsOtherAxisConstants) {
  nlohmann::json j = nlohmann::json::parse(slurp(dir_ / "gtso" / "gtso.json"));
  j["axis_constants"]["sigma_scale"] = 0.75;
  std::ofstream(dir_ / "gtso" / "gtso.json") << j.dump();
  resealOutputSet(dir_ / "gtso", "gtso");
  expectErrorAndNoOutput("axis_constants.sigma_scale");
}

TEST_F(ExportTest, RejectsNanTexel) {
  std::vector<float> t = test::fixtureTable3D();
  t[17] = std::nanf("");
  std::ofstream(dir_ / "gtso" / "gtso3d.f32", std::ios::binary)
      .write(reinterpret_cast<const char*>(t.data()), t.size() * 4);
  resealOutputSet(dir_ / "gtso", "gtso");
  expectErrorAndNoOutput("texel 17");
}

TEST_F(ExportTest, RejectsMissingCoefficient) {
  std::string json = slurp(dir_ / "fit.json");
  json.replace(json.find("\"c0\""), 4, "\"cz\"");
  std::ofstream(dir_ / "fit.json") << json;
  resealOutputSet(dir_, "fit");
  expectErrorAndNoOutput("c0");
}

// Profiles: one entry per <estimator>/fit.json in name order; a directory that is not the
// profile it claims, or whose name cannot become an identifier, is refused with nothing written.
TEST_F(ExportTest, ProfilesShipInNameOrderAndBadOnesAreRefused) {
  test::writeProfileFixture(dir_ / "profiles", "hbao", 1);
  test::writeProfileFixture(dir_ / "profiles", "gtao-runtime", 0);
  fs::create_directories(dir_ / "profiles" / "notes");  // no fit manifest: not a profile
  options_.profiles = dir_ / "profiles";
  exportAll();
  const std::string h = slurp(options_.out / "gtbake_tables.h");
  EXPECT_NE(h.find("kMultiBounceProfileCount = 2;"), std::string::npos);
  EXPECT_LT(h.find("{\"gtao-runtime\", "), h.find("{\"hbao\", "));
  EXPECT_NE(slurp(options_.out / "gtbake_tables.glsl").find("float multiBounce_gtao_runtime("),
            std::string::npos);
  fs::remove_all(options_.out);
  test::writeProfileFixture(dir_ / "profiles", "bitmask-cosine", 2, "hbao");
  expectErrorAndNoOutput("not the profile of estimator 'bitmask-cosine'");
  fs::remove_all(dir_ / "profiles" / "bitmask-cosine");
  test::writeProfileFixture(dir_ / "profiles", "Bad\"name", 2);
  expectErrorAndNoOutput("lower-case letters, digits and '-'");
  fs::remove_all(dir_ / "profiles" / "Bad\"name");
  // A profile table that is not what `gtbake fit` ships: a row that falls, a row short of G(1) =
  // 1, more nodes than the bound, albedos out of order (docs/profiles.md §8).
  const fs::path hbao = dir_ / "profiles" / "hbao";
  const std::pair<const char*, nlohmann::json> bad[] = {{"/profile/table/values/0/2", 0.2},
                                                        {"/profile/table/values/1/3", 0.9},
                                                        {"/profile/table/A_nodes", 100000},
                                                        {"/profile/table/rho/1", 0.1}};
  for (const auto& [pointer, value] : bad) {
    test::writeProfileFixture(dir_ / "profiles", "hbao", 1);
    nlohmann::json fit = nlohmann::json::parse(slurp(hbao / "fit.json"));
    fit[nlohmann::json::json_pointer(pointer)] = value;
    std::ofstream(hbao / "fit.json") << fit.dump();
    resealOutputSet(hbao, "fit");
    expectErrorAndNoOutput("profile/table");
  }
}

TEST(FloatLiteral, RoundTripsExactly) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uni(-10.0f, 10.0f);
  for (int i = 0; i < 20000; ++i) {
    const float x = i % 3 == 0 ? std::ldexp(uni(rng), -(i % 40)) : uni(rng);
    ASSERT_EQ(std::strtof(floatLiteral(x).c_str(), nullptr), x) << floatLiteral(x);
  }
  EXPECT_EQ(floatLiteral(1.0f), "1.0");
}

TEST_F(ExportTest, HeaderConstantsReadBackExactly) {
  exportAll();
  const std::string h = slurp(options_.out / "gtbake_tables.h");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(h, m, std::regex("kConeApertureU = ([^f;]+)f;")));
  EXPECT_EQ(std::strtof(m[1].str().c_str(), nullptr), float(test::kFixtureU));
  ASSERT_TRUE(std::regex_search(h, m, std::regex("kMultiBounceB\\[2\\] = \\{([^f]+)f, ([^f]+)f")));
  EXPECT_EQ(std::strtof(m[1].str().c_str(), nullptr), float(test::kFixtureCoeffs[2]));
  EXPECT_EQ(std::strtof(m[2].str().c_str(), nullptr), float(test::kFixtureCoeffs[3]));
}

// tune.json as `gtbake tune` writes it (the fields export reads), sealed as its set: one setting
// whose profile optimum is 2.5 [2, 3] m, evaluated best at 2 m with these coefficients.
void writeTuneFixture(const fs::path& dir, bool complete) {
  nlohmann::json refit = {{"a1", 0.5}, {"a0", 1.25}, {"b1", 0.75},
                          {"b0", 1.5}, {"c1", 0.25}, {"c0", 1.0}};
  nlohmann::json profile = {{"value", 2.5},
                            {"interval", {2.0, 3.0}},
                            {"at_bound", false},
                            {"grid_best", {{"value", 2.0}, {"profile_held_out", 0.125}}},
                            {"refit", refit}};
  nlohmann::json optimum = {{"paper", {{"value", 4.0}}}, {"profile", profile}};
  if (!complete) optimum["profile"].erase("refit");
  const nlohmann::json j = {
      {"results", {{"gtao-runtime", {{"radius", {{"default", 1.0}, {"optimum", optimum}}}}}}}};
  OutputSet set(dir, "tune");
  set.add("tune.json", j.dump());
  set.commit();
}

TEST_F(ExportTest, TunedSettingsShipWithTheirRefitAndBadOnesAreRefused) {
  writeTuneFixture(dir_ / "tune", true);
  options_.tune = dir_ / "tune" / "tune.json";
  exportAll();
  const std::string h = slurp(options_.out / "gtbake_tables.h");
  EXPECT_NE(h.find("kTunedSettingCount = 1;"), std::string::npos);
  EXPECT_NE(h.find("{\"gtao-runtime\", \"radius\", 1.0f, 4.0f, 2.5f, 2.0f, 3.0f, false, 2.0f, "
                   "{0.5f, 1.25f}, {0.75f, 1.5f}, {0.25f, 1.0f}, 0.125f},"),
            std::string::npos);
  const std::string glsl = slurp(options_.out / "gtbake_tables.glsl");
  EXPECT_NE(glsl.find("#define GTBAKE_TUNED_GTAO_RUNTIME_RADIUS 2.0\n"), std::string::npos);
  EXPECT_NE(glsl.find("float multiBounce_gtao_runtime_radius(float A, float albedo)"),
            std::string::npos);
  // The struct compiles and evaluates Equation 10 with the refit: at A = 1, rho = 0.5,
  // a - b + c = (0.5*0.5 + 1.25) - (0.75*0.5 + 1.5) + (0.25*0.5 + 1.0) = 0.75.
  std::ofstream(dir_ / "tuned.cpp")
      << "#include \"gtbake_tables.h\"\n"
      << "static_assert(gtbake::kTunedSettingCount == 1);\n"
      << "float f() { return gtbake::multiBounce(gtbake::kTunedSettings[0], 1.0f, 0.5f); }\n";
  const std::string cmd = std::string(GTBAKE_TEST_CXX) +
                          " -std=c++17 -fsyntax-only -Wall -Wextra -Werror -I" +
                          options_.out.string() + " " + (dir_ / "tuned.cpp").string() + " 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  fs::remove_all(options_.out);
  fs::remove_all(dir_ / "tune");
  writeTuneFixture(dir_ / "tune", false);
  expectErrorAndNoOutput("optimum/profile: missing key \"refit\"");
}

TEST_F(ExportTest, HeaderCompilesAlone) {
  exportAll();
  std::ofstream(dir_ / "consumer.cpp")
      << "#include \"gtbake_tables.h\"\n"
      << "float f() { return gtbake::gtso3DLookup(0.5f, 1.0f, 0.5f); }\n";
  const std::string cmd = std::string(GTBAKE_TEST_CXX) +
                          " -std=c++17 -fsyntax-only -Wall -Wextra -Wpedantic -Werror -I" +
                          options_.out.string() + " " + (dir_ / "consumer.cpp").string() + " 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

// glslangValidator (Debian glslang-tools) compiles the GLSL include inside a compute shader and
// the HLSL include with -D.
TEST_F(ExportTest, ShaderIncludesCompile) {
  if (std::string(GTBAKE_GLSLANG).empty() ||
      std::string(GTBAKE_GLSLANG).find("NOTFOUND") != std::string::npos) {
    GTEST_SKIP() << "glslangValidator not installed (apt-get install glslang-tools)";
  }
  for (int k = 0; k < 2; ++k)
    test::writeProfileFixture(dir_ / "profiles", test::kFixtureProfiles[k], k);
  options_.profiles = dir_ / "profiles";
  exportAll();
  const std::string glsl =
      "#version 450\nlayout(local_size_x = 1) in;\n"
      "layout(binding = 0) uniform sampler3D t3;\n"
      "layout(binding = 1) uniform sampler3D t4;\n"
      "layout(std430, binding = 2) buffer Out { float result[]; };\n" +
      slurp(options_.out / "gtbake_tables.glsl") +
      "void main() {\n  result[0] = gtso3DSample(t3, 0.5, 0.7, 0.3) + "
      "gtso4DSample(t4, 0.5, 0.7, 0.3, 0.9) + multiBounce(0.5, 0.7) + "
      "gtsoConeModel(0.5, 0.7, 0.3) + multiBounce_gtao_runtime(0.5, 0.7) + "
      "multiBounceTable_hbao(0.5, 0.7) + multiBouncePaper(0.5, 0.7);\n}\n";
  std::ofstream(dir_ / "check.comp") << glsl;
  const std::string hlsl = slurp(options_.out / "gtbake_tables.hlsl") +
                           "Texture3D<float> t3 : register(t0);\nTexture3D<float> t4 : "
                           "register(t1);\nSamplerState s : register(s0);\n"
                           "RWStructuredBuffer<float> result : register(u0);\n"
                           "[numthreads(1, 1, 1)] void main() {\n  result[0] = gtso3DSample(t3, "
                           "s, 0.5, 0.7, 0.3) + gtso4DSample(t4, s, 0.5, 0.7, 0.3, 0.9) + "
                           "multiBounce(0.5, 0.7) + gtsoConeModel(0.5, 0.7, 0.3) + "
                           "multiBounce_hbao(0.5, 0.7) + multiBounceTable_hbao(0.5, 0.7) + "
                           "multiBouncePaper(0.5, 0.7);\n}\n";
  std::ofstream(dir_ / "check.hlsl") << hlsl;
  const std::string tool = GTBAKE_GLSLANG;
  const std::string g = tool + " -V -S comp -o " + (dir_ / "check_glsl.spv").string() + " " +
                        (dir_ / "check.comp").string();
  EXPECT_EQ(std::system(g.c_str()), 0) << g;
  const std::string d = tool + " -D -V -e main -S comp -o " + (dir_ / "check.spv").string() + " " +
                        (dir_ / "check.hlsl").string();
  EXPECT_EQ(std::system(d.c_str()), 0) << d;
}

}  // namespace
}  // namespace gtbake
