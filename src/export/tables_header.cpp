#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "common/error.h"
#include "encode/bc4_layout.h"
#include "export/generated_code.h"
#include "export/runtime_sources.h"
#include "fit/multibounce_coeffs.h"
#include "runtime/gtso_runtime.h"

namespace gtbake {
namespace {

constexpr int kBlocksPerLine = 4;  // uint64 literals per line of the generated arrays

// Text for a // comment in C++, HLSL and GLSL: printable ASCII only, so nothing can end the
// comment (a line break) or splice the next line into it (a trailing backslash, or the trigraph
// "??/"); line breaks become spaces, a backslash '/', any other byte and a '?' after a '?' '_'
// (docs/limits.md §Names in outputs).
std::string oneLine(std::string text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    char& c = text[i];
    if (c == '\n' || c == '\r' || c == '\t') {
      c = ' ';
    } else if (c == '\\') {
      c = '/';
    } else if (c < 0x20 || c > 0x7E || (c == '?' && i > 0 && text[i - 1] == '?')) {
      c = '_';
    }
  }
  return text;
}

// A value from nested JSON objects as compact text, or "n/a" when absent.
std::string jsonAt(const nlohmann::json& j, std::initializer_list<const char*> path) {
  const nlohmann::json* p = &j;
  for (const char* key : path) {
    if (!p->is_object() || !p->contains(key)) return "n/a";
    p = &p->at(key);
  }
  return oneLine(p->is_string() ? p->get<std::string>() : p->dump());  // stays in a // comment
}

std::string g9(double v) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.9g", v);
  return buf;
}

std::string rawCoeffs(const std::array<double, 6>& c) {
  std::string s;
  for (double v : c) {
    char buf[40];
    std::snprintf(buf, sizeof(buf), " %.17g", v);
    s += buf;
  }
  return s;
}

std::string f(float v) {
  return floatLiteral(v) + "f";
}

void emitBlocks(std::ostringstream& o, const char* name, const Bc4Volume& volume) {
  const std::size_t blocks = volume.bytes.size() / 8;
  o << "inline constexpr std::uint64_t " << name << "[" << blocks << "] = {\n";
  for (std::size_t b = 0; b < blocks; ++b) {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(volume.bytes[8 * b + i]) << (8 * i);
    char buf[32];
    std::snprintf(buf, sizeof(buf), "0x%016" PRIx64 "ull,", v);
    o << (b % kBlocksPerLine == 0 ? "    " : " ") << buf;
    if (b % kBlocksPerLine == kBlocksPerLine - 1 || b + 1 == blocks) o << "\n";
  }
  o << "};\n";
  o << "static_assert(sizeof(" << name << ") == " << blocks * 8 << ", \"" << name
    << ": one uint64 per 4x4 block\");\n\n";
}

// The end-to-end error of one format, as "uniform max/RMS, stress max/RMS", from an end_to_end
// object (gtso.json's for float32 in table order, encode.json's for every format as shipped).
std::string endToEnd(const nlohmann::json& e2e, const char* table, const char* format) {
  const nlohmann::json* p = &e2e;
  for (const char* key : {table, "formats", format}) {
    if (!p->is_object() || !p->contains(key)) return "n/a";
    p = &p->at(key);
  }
  auto pair = [&](const char* set) {
    return jsonAt(*p, {set, "max"}) + " / " + jsonAt(*p, {set, "rms"});
  };
  return "uniform max/RMS " + pair("uniform") + ", stress " + pair("stress");
}

// "atlas: 4 x 8 tiles of 32x32x32 texels (theta_o slice w at x = 32 (w mod 4), z = 32
// floor(w / 4))" or "fold: ..." for the 4D volume.
std::string tilingText(const GeneratedCodeInput& in) {
  const GtsoLayout& l = in.layout_4d;
  const int* n = in.gtso->table4d.dims.data();
  const int nx = n[l.axis[0]], ny = n[l.axis[1]], nz = n[l.axis[2]];
  const int down = in.volume_4d[2] / nz;
  return std::string(l.tilesX == 1 ? "fold" : "atlas") + ": " + std::to_string(l.tilesX) + " x " +
         std::to_string(down) + " tiles of " + std::to_string(nx) + "x" + std::to_string(ny) + "x" +
         std::to_string(nz) + " texels (theta_o slice w at x = " + std::to_string(nx) + " (w mod " +
         std::to_string(l.tilesX) + "), z = " + std::to_string(nz) + " floor(w / " +
         std::to_string(l.tilesX) + "))";
}

// "texture x = theta_o, y = r_p, z = A" for a layout.
std::string layoutText(int dims, const GtsoLayout& l) {
  const char* names[3] = {"A", dims == 3 ? "theta_o" : "beta", "r_p"};
  return std::string("x = ") + names[l.axis[0]] + ", y = " + names[l.axis[1]] +
         ", z = " + names[l.axis[2]];
}

void emitConstants(std::ostringstream& o, const GeneratedCodeInput& in) {
  const GtsoTable& t3 = in.gtso->table3d;
  const GtsoTable& t4 = in.gtso->table4d;
  const auto& c = in.fit->linear;
  o << "inline constexpr char kGtbakeTablesVersion[] = \"" << in.version << "\";\n\n"
    << "// Multi-bounce (paper Eq. 10), {slope, intercept}: a(rho) = kMultiBounceA[0]*rho +\n"
    << "// kMultiBounceA[1], same for b and c; G = a*A^3 - b*A^2 + c*A.\n"
    << "inline constexpr float kMultiBounceA[2] = {" << f(float(c[0])) << ", " << f(float(c[1]))
    << "};\n"
    << "inline constexpr float kMultiBounceB[2] = {" << f(float(c[2])) << ", " << f(float(c[3]))
    << "};\n"
    << "inline constexpr float kMultiBounceC[2] = {" << f(float(c[4])) << ", " << f(float(c[5]))
    << "};\n"
    << "// The paper's constants (Jimenez et al. 2016, Eq. 10) under their own name, for "
       "comparison:\n"
    << "// the constants above are gtbake's refit on path-traced A (docs/fit.md).\n"
    << "inline constexpr float kMultiBouncePaperA[2] = {" << f(float(kPaperCoeffs[0])) << ", "
    << f(float(kPaperCoeffs[1])) << "};\n"
    << "inline constexpr float kMultiBouncePaperB[2] = {" << f(float(kPaperCoeffs[2])) << ", "
    << f(float(kPaperCoeffs[3])) << "};\n"
    << "inline constexpr float kMultiBouncePaperC[2] = {" << f(float(kPaperCoeffs[4])) << ", "
    << f(float(kPaperCoeffs[5])) << "};\n\n"
    << "// Cone-to-cone model: cos(alpha_s) = u^(alpha^2/2), alpha = r_p^2 (paper Eq. 26).\n"
    << "inline constexpr float kConeApertureU = " << f(float(in.gtso->u)) << ";\n"
    << "inline constexpr float kConeApertureUStdError = " << f(float(in.gtso->u_se)) << ";\n\n"
    << "// Texels per axis: 3D x = A (step-warped), y = theta_o, z = r_p; 4D x = A, y = beta,\n"
    << "// z = r_p, w = theta_o (axis maps: gtso3DAxes / gtso4DAxes above).\n"
    << "inline constexpr int kGtso3DSize[3] = {" << t3.dims[0] << ", " << t3.dims[1] << ", "
    << t3.dims[2] << "};\n"
    << "inline constexpr int kGtso4DSize[4] = {" << t4.dims[0] << ", " << t4.dims[1] << ", "
    << t4.dims[2] << ", " << t4.dims[3] << "};\n"
    << "// Texture layouts (chosen by encode with the BC4 encoder, docs/export.md): texture x, y, "
       "z\n"
    << "// hold table axes axis[0..2] of (0 = A, 1 = theta_o / beta, 2 = r_p); the 4D theta_o\n"
    << "// slices are tiles, tilesX across x. 3D: " << layoutText(3, in.layout_3d)
    << "; 4D: " << layoutText(4, in.layout_4d) << ";\n// 4D " << tilingText(in) << ".\n"
    << "inline constexpr GtsoLayout kGtso3DLayout = {{" << in.layout_3d.axis[0] << ", "
    << in.layout_3d.axis[1] << ", " << in.layout_3d.axis[2] << "}, 1};\n"
    << "inline constexpr GtsoLayout kGtso4DLayout = {{" << in.layout_4d.axis[0] << ", "
    << in.layout_4d.axis[1] << ", " << in.layout_4d.axis[2] << "}, " << in.layout_4d.tilesX
    << "};\n"
    << "// The volumes' texture extents in those layouts.\n"
    << "inline constexpr int kGtso3DVolumeSize[3] = {" << in.volume_3d[0] << ", " << in.volume_3d[1]
    << ", " << in.volume_3d[2] << "};\n"
    << "inline constexpr int kGtso4DVolumeSize[3] = {" << in.volume_4d[0] << ", " << in.volume_4d[1]
    << ", " << in.volume_4d[2] << "};\n"
    << "// Largest |decoded BC4 texel - float table texel| and the RMSE over all texels.\n"
    << "inline constexpr float kGtso3DBC4MaxAbsError = " << f(float(in.bc4_3d->max_abs)) << ";\n"
    << "inline constexpr float kGtso3DBC4Rmse = " << f(float(in.bc4_3d->rmse)) << ";\n"
    << "inline constexpr float kGtso4DBC4MaxAbsError = " << f(float(in.bc4_4d->max_abs)) << ";\n"
    << "inline constexpr float kGtso4DBC4Rmse = " << f(float(in.bc4_4d->rmse)) << ";\n\n";
}

// The engine profiles (docs/profiles.md): Equation 10 refitted on each estimator's Â.
void emitProfiles(std::ostringstream& o, const GeneratedCodeInput& in) {
  if (in.profiles == nullptr || in.profiles->empty()) return;
  o << profileGateComment(*in.profiles);
  const std::size_t shipped = shippedProfileCount(*in.profiles);
  if (shipped == 0) return;
  o << "// Engine profiles (docs/profiles.md): Equation 10 refitted on the A each screen-space\n"
    << "// estimator computes, path-traced G as the target. Feed an engine's own estimate through\n"
    << "// its estimator's profile: multiBounce(kMultiBounceProfiles[i], A, albedo). RMSE of G on\n"
    << "// that estimator's A with the paper's constants and with the profile held out by scene\n"
    << "// (each scene scored by the profile fitted without it); bandMax: the largest\n"
    << "// scene-jackknife SE of the profile's G.\n"
    << "struct GtbakeMultiBounceProfile {\n"
    << "  const char* estimator;\n"
    << "  float a[2], b[2], c[2];  // {slope, intercept} in rho, as kMultiBounceA/B/C\n"
    << "  float rmsePaper, rmseHeldOut, bandMax;\n"
    << "};\n"
    << "inline constexpr int kMultiBounceProfileCount = " << shipped << ";\n"
    << "inline constexpr GtbakeMultiBounceProfile kMultiBounceProfiles[" << shipped << "] = {\n";
  for (const ProfileInput& p : *in.profiles) {
    if (!p.gate.shipped) continue;
    const auto& c = p.linear;
    o << "    {\"" << p.estimator << "\", {" << f(float(c[0])) << ", " << f(float(c[1])) << "}, {"
      << f(float(c[2])) << ", " << f(float(c[3])) << "}, {" << f(float(c[4])) << ", "
      << f(float(c[5])) << "}, " << f(float(p.rmse_paper)) << ", " << f(float(p.rmse_held_out))
      << ", " << f(float(p.band_max)) << "},\n";
  }
  o << "};\n"
    << "inline float multiBounce(const GtbakeMultiBounceProfile& p, float A, float albedo) {\n"
    << "  return gtsoMultiBounce(p.a, p.b, p.c, A, albedo);\n"
    << "}\n\n";
}

// The monotone 2D tables shipped beside the cubic of the profiles whose cubic is not adequate
// (docs/profiles.md §8), as arrays and one bilinear lookup; only for shipped profiles.
void emitProfileTables(std::ostringstream& o, const GeneratedCodeInput& in) {
  if (in.profiles == nullptr) return;
  std::vector<const ProfileInput*> tables;
  for (const ProfileInput& p : *in.profiles) {
    if (p.gate.shipped && p.table_nodes > 0) tables.push_back(&p);
  }
  o << "// Profile tables (docs/profiles.md §8): where an estimator's cubic is not adequate (its\n"
    << "// RMSE more than 5% above the floor of any function of (A, albedo)), G at `nodes` values "
       "of\n"
    << "// A (0 ... 1) for each albedo in rho[], non-decreasing in A with G(1) = 1; linear in A\n"
    << "// between nodes and in the albedo between rows (clamped to the rows). rmseHeldOut: RMSE "
       "of\n"
    << "// G with the table fitted without each scene. Use: multiBounce(kMultiBounceTables[i], A,\n"
    << "// albedo).\n"
    << "struct GtbakeMultiBounceTable {\n"
    << "  const char* estimator;\n"
    << "  int nodes, rows;\n"
    << "  const float* rho;     // [rows], ascending\n"
    << "  const float* values;  // [rows][nodes]\n"
    << "  float rmseHeldOut;\n"
    << "};\n"
    << "inline float gtbakeTableRow(const GtbakeMultiBounceTable& t, int row, float A) {\n"
    << "  const float x = (A < 0.0f ? 0.0f : A > 1.0f ? 1.0f : A) * float(t.nodes - 1);\n"
    << "  const int i = int(x) < t.nodes - 2 ? int(x) : t.nodes - 2;\n"
    << "  const float* v = t.values + row * t.nodes;\n"
    << "  return v[i] + (x - float(i)) * (v[i + 1] - v[i]);\n"
    << "}\n"
    << "inline float multiBounce(const GtbakeMultiBounceTable& t, float A, float albedo) {\n"
    << "  int j0 = 0, j1 = 0;\n"
    << "  float s = 0.0f;\n"
    << "  if (albedo >= t.rho[t.rows - 1]) {\n"
    << "    j0 = j1 = t.rows - 1;\n"
    << "  } else if (albedo > t.rho[0]) {\n"
    << "    for (int j = 0; j < t.rows - 1; ++j) j0 = t.rho[j] < albedo ? j : j0;\n"
    << "    j1 = j0 + 1;\n"
    << "    s = (albedo - t.rho[j0]) / (t.rho[j1] - t.rho[j0]);\n"
    << "  }\n"
    << "  const float g0 = gtbakeTableRow(t, j0, A);\n"
    << "  return g0 + s * (gtbakeTableRow(t, j1, A) - g0);\n"
    << "}\n"
    << "inline constexpr int kMultiBounceTableCount = " << tables.size() << ";\n";
  for (const ProfileInput* p : tables) {
    const std::string id = profileIdentifier(p->estimator);
    o << "inline constexpr float kMultiBounceTableRho_" << id << "[" << p->table_rhos.size()
      << "] = {";
    for (std::size_t j = 0; j < p->table_rhos.size(); ++j)
      o << (j ? ", " : "") << f(float(p->table_rhos[j]));
    o << "};\ninline constexpr float kMultiBounceTableValues_" << id << "["
      << p->table_values.size() << "] = {";
    for (std::size_t i = 0; i < p->table_values.size(); ++i)
      o << (i % 8 == 0 ? "\n    " : " ") << f(float(p->table_values[i])) << ",";
    o << "};\n";
  }
  if (tables.empty()) {
    o << "\n";
    return;
  }
  o << "inline constexpr GtbakeMultiBounceTable kMultiBounceTables[" << tables.size() << "] = {\n";
  for (const ProfileInput* p : tables) {
    const std::string id = profileIdentifier(p->estimator);
    o << "    {\"" << p->estimator << "\", " << p->table_nodes << ", " << p->table_rhos.size()
      << ", kMultiBounceTableRho_" << id << ", kMultiBounceTableValues_" << id << ", "
      << f(float(p->table_held_out_rmse)) << "},\n";
  }
  o << "};\n\n";
}

// The tuned settings (docs/tune.md), each with the profile refitted where it was evaluated.
void emitTunedSettings(std::ostringstream& o, const GeneratedCodeInput& in) {
  if (in.tuned == nullptr || in.tuned->empty()) return;
  o << "// Tuned settings (docs/tune.md, tune/tune.json): per screen-space estimator and setting,\n"
    << "// one at a time with the others at their defaults, the value minimising the RMSE of G\n"
    << "// against path tracing with the paper's constants (paperBest) and with Equation 10\n"
    << "// refitted at each value (profileBest, its 95% scene-level interval [profileLow,\n"
    << "// profileHigh]; atBound: at the grid's end, the data want a value beyond it). gridValue "
       "is\n"
    << "// the evaluated value with the lowest RMSE under the refit, a/b/c the profile refitted "
       "there: run the\n"
    << "// pass at gridValue and feed its A to multiBounce(setting, A, albedo); rmseHeldOut is\n"
    << "// that pair's RMSE of G, each scene scored by the refit without it. The profiles above\n"
    << "// are fitted at the defaults.\n"
    << "struct GtbakeTunedSetting {\n"
    << "  const char* estimator;\n"
    << "  const char* setting;\n"
    << "  float defaultValue, paperBest, profileBest, profileLow, profileHigh;\n"
    << "  bool atBound;\n"
    << "  float gridValue;\n"
    << "  float a[2], b[2], c[2];  // {slope, intercept} in rho, as kMultiBounceA/B/C\n"
    << "  float rmseHeldOut;\n"
    << "};\n"
    << "inline constexpr int kTunedSettingCount = " << in.tuned->size() << ";\n"
    << "inline constexpr GtbakeTunedSetting kTunedSettings[" << in.tuned->size() << "] = {\n";
  for (const TunedSettingInput& t : *in.tuned) {
    const auto& c = t.linear;
    o << "    {\"" << t.estimator << "\", \"" << t.setting << "\", " << f(float(t.default_value))
      << ", " << f(float(t.paper_best)) << ", " << f(float(t.profile_best)) << ", "
      << f(float(t.profile_low)) << ", " << f(float(t.profile_high)) << ", "
      << (t.at_bound ? "true" : "false") << ", " << f(float(t.grid_value)) << ", {"
      << f(float(c[0])) << ", " << f(float(c[1])) << "}, {" << f(float(c[2])) << ", "
      << f(float(c[3])) << "}, {" << f(float(c[4])) << ", " << f(float(c[5])) << "}, "
      << f(float(t.rmse_held_out)) << "},\n";
  }
  o << "};\n"
    << "inline float multiBounce(const GtbakeTunedSetting& s, float A, float albedo) {\n"
    << "  return gtsoMultiBounce(s.a, s.b, s.c, A, albedo);\n"
    << "}\n\n";
}

// The physical-input entry points: BC4 from the arrays above, and per-format variants reading
// texels the caller loaded (gtso3d_r16.dds etc., x fastest) in the same layout.
void emitEntryPoints(std::ostringstream& o) {
  o << R"(// S3(A, beta, r_p): specular occlusion with bent normal = n, from the BC4 table above.
inline float gtso3DLookup(float A, float cosBeta, float rp) {
  const GtsoVolume v{GtsoTexelFormat::kBc4, kGtso3DBC4, kGtso3DVolumeSize[0],
                     kGtso3DVolumeSize[1], kGtso3DVolumeSize[2]};
  return gtso3DLookup(v, kGtso3DSize, A, cosBeta, rp, kGtso3DLayout);
}
// S4(A, beta, r_p, theta_o) from the tiled BC4 table: two trilinear fetches and a lerp.
inline float gtso4DLookup(float A, float cosBeta, float rp, float cosThetaO) {
  const GtsoVolume v{GtsoTexelFormat::kBc4, kGtso4DBC4, kGtso4DVolumeSize[0],
                     kGtso4DVolumeSize[1], kGtso4DVolumeSize[2]};
  return gtso4DLookup(v, kGtso4DSize, A, cosBeta, rp, cosThetaO, kGtso4DLayout);
}
// The same lookups on R16_UNORM or R8_UNORM texels in texture order (the payloads of
// gtso3d_r16.dds, gtso3d_r8.dds, ..., kGtso3DVolumeSize / kGtso4DVolumeSize texels, x fastest,
// in kGtso3DLayout / kGtso4DLayout like the BC4 volumes).
template <class Texel>
inline float gtso3DLookupAs(GtsoTexelFormat format, const Texel* texels, float A, float cosBeta,
                            float rp) {
  const GtsoVolume v{format, texels, kGtso3DVolumeSize[0], kGtso3DVolumeSize[1],
                     kGtso3DVolumeSize[2]};
  return gtso3DLookup(v, kGtso3DSize, A, cosBeta, rp, kGtso3DLayout);
}
template <class Texel>
inline float gtso4DLookupAs(GtsoTexelFormat format, const Texel* texels, float A, float cosBeta,
                            float rp, float cosThetaO) {
  const GtsoVolume v{format, texels, kGtso4DVolumeSize[0], kGtso4DVolumeSize[1],
                     kGtso4DVolumeSize[2]};
  return gtso4DLookup(v, kGtso4DSize, A, cosBeta, rp, cosThetaO, kGtso4DLayout);
}
inline float gtso3DLookupR16(const std::uint16_t* texels, float A, float cosBeta, float rp) {
  return gtso3DLookupAs(GtsoTexelFormat::kR16, texels, A, cosBeta, rp);
}
inline float gtso3DLookupR8(const std::uint8_t* texels, float A, float cosBeta, float rp) {
  return gtso3DLookupAs(GtsoTexelFormat::kR8, texels, A, cosBeta, rp);
}
// float32: the tables of `gtbake gtso` (gtso3d.f32, gtso4d.f32), which stay in table order
// (x = A, y = theta_o / beta, z = r_p, 4D w = theta_o folded: tilesX 1), whatever the layout
// above.
inline float gtso3DLookupFloat(const float* texels, float A, float cosBeta, float rp) {
  const GtsoVolume v{GtsoTexelFormat::kFloat32, texels, kGtso3DSize[0], kGtso3DSize[1],
                     kGtso3DSize[2]};
  return gtso3DLookup(v, kGtso3DSize, A, cosBeta, rp);
}
inline float gtso4DLookupR16(const std::uint16_t* texels, float A, float cosBeta, float rp,
                             float cosThetaO) {
  return gtso4DLookupAs(GtsoTexelFormat::kR16, texels, A, cosBeta, rp, cosThetaO);
}
inline float gtso4DLookupR8(const std::uint8_t* texels, float A, float cosBeta, float rp,
                            float cosThetaO) {
  return gtso4DLookupAs(GtsoTexelFormat::kR8, texels, A, cosBeta, rp, cosThetaO);
}
inline float gtso4DLookupFloat(const float* texels, float A, float cosBeta, float rp,
                               float cosThetaO) {
  const GtsoVolume v{GtsoTexelFormat::kFloat32, texels, kGtso4DSize[0], kGtso4DSize[1],
                     kGtso4DSize[2] * kGtso4DSize[3]};
  return gtso4DLookup(v, kGtso4DSize, A, cosBeta, rp, cosThetaO);
}

// Cone-to-cone specular occlusion (paper Eq. 19) with the fitted aperture constant. Takes
// perceptual roughness rp (what Unity HDRP passes); cos(alpha_s) = u^(alpha^2/2), alpha = rp^2.
inline float gtsoConeModel(float A, float cosBeta, float rp) {
  return gtsoConeModel(kConeApertureU, A, cosBeta, rp);
}
// The same cone for an engine that passes the GGX width alpha = rp^2 (Filament, XeGTAO).
inline float gtsoConeModelFromAlpha(float A, float cosBeta, float alpha) {
  return gtsoConeModel(kConeApertureU, A, cosBeta, std::sqrt(alpha));
}

// Multi-bounce G(A, rho) (paper Eq. 10) with the constants above, unclamped.
inline float multiBounce(float A, float albedo) {
  return gtsoMultiBounce(kMultiBounceA, kMultiBounceB, kMultiBounceC, A, albedo);
}

)";
}

// The closed-form S3 (gtso.json closed_form): its coefficients and the physical-input entry
// point over the template gtsoS3ClosedForm of gtso_runtime.h.
void emitClosedForm(std::ostringstream& o, const GeneratedCodeInput& in) {
  o << "// Closed-form S3 without a sampler (gtsoS3ClosedForm above; gtso.json closed_form): "
    << kGtsoS3ClosedFormSets << " sets\n// of " << kGtsoS3ClosedFormBasis
    << " polynomial coefficients. Error vs the integrator on the test points: r_p >= 0.1 max "
    << jsonAt(in.gtso->json, {"closed_form", "test", "errors", "r_p_ge_0.1", "max"}) << ", RMS "
    << jsonAt(in.gtso->json, {"closed_form", "test", "errors", "r_p_ge_0.1", "rms"})
    << ";\n// r_p < 0.1 max "
    << jsonAt(in.gtso->json, {"closed_form", "test", "errors", "r_p_lt_0.1", "max"}) << ", RMS "
    << jsonAt(in.gtso->json, {"closed_form", "test", "errors", "r_p_lt_0.1", "rms"})
    << ". ALU: " << kGtsoS3ClosedFormAlu << ".\n"
    << "inline constexpr float kGtsoS3ClosedForm[" << kGtsoS3ClosedFormCoeffs << "] = {";
  for (std::size_t i = 0; i < in.gtso->s3_closed_form.size(); ++i) {
    o << (i % kGtsoS3ClosedFormBasis == 0 ? "\n    " : " ")
      << f(static_cast<float>(in.gtso->s3_closed_form[i])) << ",";
  }
  o << "\n};\n"
    << "// S3(A, beta, r_p) with bent normal = n from the closed form: the inputs of "
       "gtso3DLookup,\n"
    << "// no texture.\n"
    << "inline float gtsoS3ClosedForm(float A, float cosBeta, float rp) {\n"
    << "  return gtsoS3ClosedForm(kGtsoS3ClosedForm, A, cosBeta, rp);\n}\n\n";
}

}  // namespace

std::string floatLiteral(float value) {
  // The readers bound every shipped number (export_inputs.cpp); this keeps the header compiling.
  if (!std::isfinite(value)) throw Error("internal: a non-finite constant reached generated code");
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.9g", static_cast<double>(value));
  std::string s = buf;
  if (s.find_first_of(".eEni") == std::string::npos) s += ".0";
  return s;
}

std::string profileIdentifier(const std::string& estimator) {
  std::string id = estimator;
  std::replace(id.begin(), id.end(), '-', '_');
  return id;
}

std::string profileGateComment(const std::vector<ProfileInput>& profiles) {
  std::string out =
      "// Profile gate (docs/profiles.md §9): shipped only if monotone in A, G(1, rho) = 1, G >= "
      "0\n"
      "// and its held-out RMSE of G beats the paper's constants on the same A.\n";
  for (const ProfileInput& p : profiles) {
    out += "//   " + p.estimator + (p.gate.shipped ? ": shipped; " : ": absent; ") + p.gate.reason +
           "\n";
  }
  return out;
}

std::size_t shippedProfileCount(const std::vector<ProfileInput>& profiles) {
  return static_cast<std::size_t>(std::count_if(
      profiles.begin(), profiles.end(), [](const ProfileInput& p) { return p.gate.shipped; }));
}

namespace {

// The cone aperture u's provenance lines: from validate_gtso.json (scene-level interval, law,
// data) when export was given it, else gtso.json's table fit.
void coneProvenance(std::ostringstream& o, const GeneratedCodeInput& in) {
  const nlohmann::json& gj = in.gtso->json;
  char u_raw[40];
  std::snprintf(u_raw, sizeof(u_raw), "%.17g", in.gtso->u);
  if (in.gtso->validate_gtso.is_null()) {
    o << "// Cone aperture u = " << u_raw << " (SE " << g9(in.gtso->u_se) << "), convention "
      << jsonAt(gj, {"cone", "convention"}) << "\n";
  } else {
    const nlohmann::json& vj = in.gtso->validate_gtso;
    o << "// Cone aperture u = " << u_raw << " from validate_gtso.json, "
      << (vj.contains("u_scene_interval") ? "scene-level 95% interval (delete-one-scene jackknife "
                                            "of log10 u) ["
                                          : "5% profile interval [")
      << g9(in.gtso->u_low) << ", " << g9(in.gtso->u_high) << "], SE " << g9(in.gtso->u_se)
      << ", convention " << jsonAt(vj, {"u_fit", "alpha", "convention"}) << "\n"
      << "//   objective: " << jsonAt(vj, {"u_fit", "objective"}) << "\n"
      << "//   law by a paired scene-level test of held-out RMSE: "
      << jsonAt(vj, {"u_law", "chosen"}) << " (shipped here: u^(alpha^2/2))\n"
      << "//   data: " << jsonAt(vj, {"sweep"}) << "\n"
      << "//   RMSE at u, 0.01, 0.244: " << jsonAt(vj, {"u_fit", "alpha", "all", "rmse"}) << ", "
      << jsonAt(vj, {"u_fit", "alpha", "all", "rmse_u_0.01"}) << ", "
      << jsonAt(vj, {"u_fit", "alpha", "all", "rmse_u_0.244"})
      << "; perceptual reading u^(r_p^2/2): " << jsonAt(vj, {"u_fit", "perceptual", "all"}) << "\n"
      << "//   diagnostic: u fitted to the 3D table (gtso.json) = " << jsonAt(gj, {"cone", "u"})
      << "\n";
  }
}

}  // namespace

std::string provenanceComment(const GeneratedCodeInput& in) {
  const nlohmann::json& fj = in.fit->json;
  const nlohmann::json& gj = in.gtso->json;
  std::ostringstream o;
  o << "// Generated by gtbake " << in.version << " (`gtbake export`); do not edit.\n"
    << "// Command line: " << oneLine(in.command_line) << "\n"
    << "// fit.json: version " << jsonAt(fj, {"version"}) << "; sweep spp "
    << jsonAt(fj, {"sweep", "spp"}) << ", bounces " << jsonAt(fj, {"sweep", "bounces"}) << "\n"
    << "//   raw (double) a1, a0, b1, b0, c1, c0:" << rawCoeffs(in.fit->linear)
    << "; shipped as the nearest floats\n"
    << "//   refit RMSE " << jsonAt(fj, {"errors", "refit", "rmse"}) << ", max |err| "
    << jsonAt(fj, {"errors", "refit", "max_abs"}) << "; Monte Carlo standard errors a1..c0:";
  for (double se : in.fit->linear_se) o << " " << g9(se);
  o << "\n//   shipped constants vs refit: max |dG| "
    << jsonAt(fj, {"shipped", "max_curve_difference", "value"})
    << " at A = " << jsonAt(fj, {"shipped", "max_curve_difference", "A"})
    << ", rho = " << jsonAt(fj, {"shipped", "max_curve_difference", "rho"}) << "\n"
    << "//   scene-level band (fit.json scene_jackknife): max SE of G "
    << jsonAt(fj, {"scene_jackknife", "band_max", "value"})
    << " at A = " << jsonAt(fj, {"scene_jackknife", "band_max", "A"})
    << ", rho = " << jsonAt(fj, {"scene_jackknife", "band_max", "rho"}) << "; weighting "
    << jsonAt(fj, {"settings", "weighting"}) << "; views " << jsonAt(fj, {"sweep", "views"})
    << "\n//   shipped constants by range of A (docs/fit.md section 5): "
    << jsonAt(fj, {"shipped", "verdict", "headline"}) << "\n"
    << "// gtso.json: version " << jsonAt(gj, {"version"}) << "; roughness "
    << jsonAt(gj, {"roughness_convention"}) << "; texel rule " << jsonAt(gj, {"texel_rule"})
    << "\n";
  for (const GtsoTable* t : {&in.gtso->table3d, &in.gtso->table4d}) {
    const std::string reference_error = jsonAt(t->meta, {"max_abs_error_vs_reference"});
    const char* key = t == &in.gtso->table3d ? "3d" : "4d";
    const GtsoLayout& layout = t == &in.gtso->table3d ? in.layout_3d : in.layout_4d;
    o << "//   " << oneLine(t->file) << ": lobe-grid rectangles "
      << jsonAt(t->meta, {"lobe_grid_rectangles"}) << ", max |S - reference| "
      << (reference_error == "null" ? "over all texels not measured by this run" : reference_error)
      << "; sampled texel check vs 16x reference: max "
      << jsonAt(t->meta, {"texel_check", "max_abs"}) << ", RMS "
      << jsonAt(t->meta, {"texel_check", "rms"}) << " over "
      << jsonAt(t->meta, {"texel_check", "lines"})
      << " random lines, half at the theta_o ends (seed "
      << jsonAt(t->meta, {"texel_check", "seed"}) << ")"
      << "\n//     end to end vs direct integration (max over seeds / mean RMS): float32 in table "
         "order (gtso.json) "
      << endToEnd(gj.contains("end_to_end") ? gj["end_to_end"] : nlohmann::json(), key, "float32")
      << "\n//       as shipped (layout " << layoutSwizzle(layout) << ", encode.json): BC4 "
      << endToEnd(in.end_to_end, key, "bc4") << "\n//       R16 "
      << endToEnd(in.end_to_end, key, "r16") << "\n//       R8 "
      << endToEnd(in.end_to_end, key, "r8") << "; recommended "
      << jsonAt(in.end_to_end, {key, "recommended"}) << "\n";
  }
  coneProvenance(o, in);
  o << "//   errors of S_cone vs S3: " << jsonAt(gj, {"cone", "errors"}) << "\n"
    << "// BC4 vs the float tables (exact per-block optimum, D3D float decode): 3D RMSE "
    << g9(in.bc4_3d->rmse) << ", max " << g9(in.bc4_3d->max_abs) << "; 4D RMSE "
    << g9(in.bc4_4d->rmse) << ", max " << g9(in.bc4_4d->max_abs) << "\n"
    << "// Roughness axes use perceptual roughness r_p, GGX alpha = r_p^2.\n"
    << "// Texel i of an axis holds the inverse axis map of i/(N-1); lookups remap by half a\n"
    << "// texel: u = (t*(N-1) + 0.5)/N. The 4D table's theta_o slices are tiles of the volume,\n"
    << "// " << tilingText(in) << ";\n"
    << "// sampled as two trilinear fetches (one per neighbouring slice's tile) + a lerp.\n";
  return o.str();
}

std::string makeTablesHeader(const GeneratedCodeInput& in) {
  std::ostringstream o;
  o << "// gtbake_tables.h: GTAO multi-bounce constants, the GTSO cone constant and BC4 tables.\n"
    << provenanceComment(in)
    << "// Storage: kGtso3DBC4[i] / kGtso4DBC4[i] is BC4_UNORM block i as a little-endian uint64\n"
    << "// (byte j of the block = bits 8j..8j+7: red_0, red_1, then 48 index bits, texel 0 "
       "lowest),\n"
    << "// blocks in texture memory order: z slices, rows of blocks, blocks left to right.\n"
    << "// The lookup code below the provenance is src/runtime/gtso_runtime.h verbatim.\n"
    << "#pragma once\n\n"
    << kRuntimeLookupHeader << "\nnamespace gtbake {\n\n";
  emitConstants(o, in);
  emitBlocks(o, "kGtso3DBC4", *in.bc4_3d);
  emitBlocks(o, "kGtso4DBC4", *in.bc4_4d);
  emitEntryPoints(o);
  o << "// Multi-bounce G(A, rho) with the paper's constants (kMultiBouncePaperA/B/C), unclamped.\n"
    << "inline float multiBouncePaper(float A, float albedo) {\n"
    << "  return gtsoMultiBounce(kMultiBouncePaperA, kMultiBouncePaperB, kMultiBouncePaperC, A, "
       "albedo);\n}\n\n";
  emitProfiles(o, in);
  emitProfileTables(o, in);
  emitTunedSettings(o, in);
  emitClosedForm(o, in);
  o << "}  // namespace gtbake\n";
  return o.str();
}

}  // namespace gtbake
