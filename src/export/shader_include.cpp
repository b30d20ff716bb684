// The HLSL and GLSL includes: provenance, the language macros, the constants (from the same C++
// constants the C++ lookup uses) and src/runtime/gtso_runtime.shader verbatim.
#include <cctype>
#include <cstdio>
#include <sstream>

#include "encode/bc4_layout.h"
#include "export/generated_code.h"
#include "export/runtime_sources.h"
#include "fit/multibounce_coeffs.h"
#include "runtime/gtso_runtime.h"

namespace gtbake {
namespace {

struct Dialect {
  const char* name;
  const char* float2;
  const char* float3;
  const char* float4;
  const char* constant;  // storage qualifier of a file-scope constant
  const char* macros;    // GTSO_VEC3, GTSO_VEC4, GTSO_ATAN2, GTSO_TEXTURE, GTSO_SAMPLE
};

constexpr Dialect kHlsl = {"hlsl",
                           "float2",
                           "float3",
                           "float4",
                           "static const",
                           "#define GTSO_VEC3 float3\n"
                           "#define GTSO_VEC4 float4\n"
                           "#define GTSO_ATAN2(y, x) atan2(y, x)\n"
                           "#define GTSO_TEXTURE Texture3D<float> tex, SamplerState linearClamp\n"
                           "#define GTSO_SAMPLE(c) tex.SampleLevel(linearClamp, c, 0.0)\n"};
constexpr Dialect kGlsl = {"glsl",
                           "vec2",
                           "vec3",
                           "vec4",
                           "const",
                           "#define GTSO_VEC3 vec3\n"
                           "#define GTSO_VEC4 vec4\n"
                           "#define GTSO_ATAN2(y, x) atan(y, x)\n"
                           "#define GTSO_TEXTURE sampler3D tex\n"
                           "#define GTSO_SAMPLE(c) textureLod(tex, c, 0.0).r\n"};

// A float literal both languages read as a 32-bit float (no suffix: HLSL and GLSL both take
// "1.5" as float).
std::string lit(double v) {
  return floatLiteral(static_cast<float>(v));
}

// The closed-form S3's coefficients (gtso.json closed_form) for gtsoS3ClosedForm.
std::string closedFormConstants(const GeneratedCodeInput& in, const Dialect& d) {
  std::ostringstream o;
  const bool hlsl = std::string(d.name) == "hlsl";
  o << "// Closed-form S3 (gtsoS3ClosedForm): " << kGtsoS3ClosedFormSets << " sets of "
    << kGtsoS3ClosedFormBasis << " polynomial coefficients (gtso.json closed_form).\n"
    << "#define kGtsoS3ClosedFormAlphaFloorF " << lit(kGtsoS3ClosedFormAlphaFloor) << "\n"
    << d.constant << " float kGtsoS3ClosedForm[" << kGtsoS3ClosedFormCoeffs
    << "] = " << (hlsl ? "{" : "float[" + std::to_string(kGtsoS3ClosedFormCoeffs) + "](");
  for (std::size_t i = 0; i < in.gtso->s3_closed_form.size(); ++i) {
    o << (i == 0 ? "" : ",") << (i % kGtsoS3ClosedFormBasis == 0 ? "\n    " : " ")
      << lit(in.gtso->s3_closed_form[i]);
  }
  o << (hlsl ? "};\n\n" : ");\n\n");
  return o.str();
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// Equation 10 with the paper's constants under their own name, for comparison with the refit.
std::string paperFunction() {
  const auto& c = kPaperCoeffs;
  return "\n// Multi-bounce G(A, rho) with the paper's constants (Jimenez et al. 2016, Eq. 10),\n"
         "// unclamped; multiBounce uses gtbake's refit on path-traced A (docs/fit.md).\n"
         "float multiBouncePaper(float A, float albedo) {\n  return gtsoMultiBounce(" +
         lit(c[0]) + ", " + lit(c[1]) + ", " + lit(c[2]) + ", " + lit(c[3]) + ", " + lit(c[4]) +
         ", " + lit(c[5]) + ", A, albedo);\n}\n";
}

// One function per engine profile (docs/profiles.md), after the runtime template.
std::string profileFunctions(const GeneratedCodeInput& in) {
  if (in.profiles == nullptr || in.profiles->empty()) return "";
  std::ostringstream o;
  o << "\n" << profileGateComment(*in.profiles);
  if (shippedProfileCount(*in.profiles) == 0) return o.str();
  o << "// Engine profiles (docs/profiles.md): Equation 10 refitted on the A each screen-space\n"
    << "// estimator computes. RMSE of G on that A: paper's constants | profile held out by "
       "scene.\n";
  for (const ProfileInput& p : *in.profiles) {
    if (!p.gate.shipped) continue;
    const auto& c = p.linear;
    o << "// " << p.estimator << ": " << lit(p.rmse_paper) << " | " << lit(p.rmse_held_out) << "\n"
      << "float multiBounce_" << profileIdentifier(p.estimator) << "(float A, float albedo) {\n"
      << "  return gtsoMultiBounce(" << lit(c[0]) << ", " << lit(c[1]) << ", " << lit(c[2]) << ", "
      << lit(c[3]) << ", " << lit(c[4]) << ", " << lit(c[5]) << ", A, albedo);\n}\n";
  }
  return o.str();
}

// The profile tables (docs/profiles.md §8): per table two constant arrays and
// multiBounceTable_<estimator>(A, albedo), the header's bilinear lookup written out.
std::string profileTableFunctions(const GeneratedCodeInput& in, const Dialect& d) {
  if (in.profiles == nullptr) return "";
  const bool hlsl = std::string(d.name) == "hlsl";
  const auto array = [&](const std::string& name, const std::vector<double>& v) {
    std::ostringstream a;
    a << d.constant << " float " << name << "[" << v.size()
      << "] = " << (hlsl ? "{" : "float[" + std::to_string(v.size()) + "](");
    for (std::size_t i = 0; i < v.size(); ++i)
      a << (i ? "," : "") << (i % 8 == 0 ? "\n    " : " ") << lit(v[i]);
    a << (hlsl ? "};\n" : ");\n");
    return a.str();
  };
  std::ostringstream o;
  for (const ProfileInput& p : *in.profiles) {
    if (!p.gate.shipped || p.table_nodes == 0) continue;
    const std::string id = profileIdentifier(p.estimator);
    const std::string rho = "kMultiBounceTableRho_" + id, g = "kMultiBounceTable_" + id;
    const std::string rows = std::to_string(p.table_rhos.size());
    const std::string nodes = std::to_string(p.table_nodes);
    o << "\n// Profile table of " << p.estimator << " (docs/profiles.md §8; gtbake_tables.h\n"
      << "// GtbakeMultiBounceTable has the lookup): RMSE of G held out by scene "
      << lit(p.table_held_out_rmse) << "\n"
      << array(rho, p.table_rhos) << array(g, p.table_values) << "float gtbakeTableRow_" << id
      << "(int row, float A) {\n"
      << "  float x = clamp(A, 0.0, 1.0) * float(" << nodes << " - 1);\n"
      << "  int i = min(int(x), " << nodes << " - 2);\n"
      << "  float v0 = " << g << "[row * " << nodes << " + i];\n"
      << "  return v0 + (x - float(i)) * (" << g << "[row * " << nodes << " + i + 1] - v0);\n"
      << "}\n"
      << "float multiBounceTable_" << id << "(float A, float albedo) {\n"
      << "  int j0 = 0;\n  int j1 = 0;\n  float s = 0.0;\n"
      << "  if (albedo >= " << rho << "[" << rows << " - 1]) {\n"
      << "    j0 = " << rows << " - 1;\n    j1 = j0;\n"
      << "  } else if (albedo > " << rho << "[0]) {\n"
      << "    for (int j = 0; j < " << rows << " - 1; ++j) j0 = " << rho
      << "[j] < albedo ? j : j0;\n"
      << "    j1 = j0 + 1;\n"
      << "    s = (albedo - " << rho << "[j0]) / (" << rho << "[j1] - " << rho << "[j0]);\n"
      << "  }\n"
      << "  float g0 = gtbakeTableRow_" << id << "(j0, A);\n"
      << "  return g0 + s * (gtbakeTableRow_" << id << "(j1, A) - g0);\n"
      << "}\n";
  }
  return o.str();
}

// One constant and one Equation 10 function per tuned setting (docs/tune.md).
std::string tunedFunctions(const GeneratedCodeInput& in) {
  if (in.tuned == nullptr || in.tuned->empty()) return "";
  std::ostringstream o;
  o << "\n// Tuned settings (docs/tune.md; gtbake_tables.h kTunedSettings has the intervals): the\n"
    << "// evaluated value with the lowest RMSE of G under the profile refit, and that refit.\n";
  for (const TunedSettingInput& t : *in.tuned) {
    const auto& c = t.linear;
    const std::string id = profileIdentifier(t.estimator) + "_" + t.setting;
    o << "// " << t.estimator << " " << t.setting << ": default " << lit(t.default_value)
      << ", best with the paper's constants " << lit(t.paper_best) << ", with the refit "
      << lit(t.profile_best) << " [" << lit(t.profile_low) << ", " << lit(t.profile_high) << "]"
      << (t.at_bound ? " (at the grid's end)" : "") << "; RMSE of G held out "
      << lit(t.rmse_held_out) << "\n"
      << "#define GTBAKE_TUNED_" << upper(id) << " " << lit(t.grid_value) << "\n"
      << "float multiBounce_" << id << "(float A, float albedo) {\n"
      << "  return gtsoMultiBounce(" << lit(c[0]) << ", " << lit(c[1]) << ", " << lit(c[2]) << ", "
      << lit(c[3]) << ", " << lit(c[4]) << ", " << lit(c[5]) << ", A, albedo);\n}\n";
  }
  return o.str();
}

}  // namespace

std::string makeShaderInclude(const GeneratedCodeInput& in, ShaderLanguage language) {
  const Dialect& d = language == ShaderLanguage::kHlsl ? kHlsl : kGlsl;
  const GtsoTable& t3 = in.gtso->table3d;
  const GtsoTable& t4 = in.gtso->table4d;
  const auto& c = in.fit->linear;
  std::ostringstream o;
  o << "// gtbake_tables." << d.name
    << ": GTAO multi-bounce, GTSO cone model and table lookups (include file).\n"
    << provenanceComment(in) << "// Textures: gtso3d.dds/.ktx2 (" << in.volume_3d[0] << "x"
    << in.volume_3d[1] << "x" << in.volume_3d[2] << ") and gtso4d.dds/.ktx2 (" << in.volume_4d[0]
    << "x" << in.volume_4d[1] << "x" << in.volume_4d[2]
    << "), BC4_UNORM (or the _r16 / _r8 files), sampled with a linear, clamp-to-edge sampler.\n"
    << "// Their layouts (export.json): GTSO_3D_LAYOUT / GTSO_4D_LAYOUT below take the table axes\n"
    << "// (A, theta_o or beta, r_p) to texture (x, y, z).\n"
    << "// The functions below the constants are src/runtime/gtso_runtime.shader verbatim.\n"
    << "#ifndef GTBAKE_TABLES_INCLUDED\n#define GTBAKE_TABLES_INCLUDED\n\n"
    << d.macros << "#define GTSO_3D_LAYOUT(c) (c)." << layoutSwizzle(in.layout_3d) << "\n"
    << "#define GTSO_4D_LAYOUT(c) (c)." << layoutSwizzle(in.layout_4d) << "\n\n"
    << "// {slope, intercept}: a(rho) = x*rho + y; G = a*A^3 - b*A^2 + c*A (paper Eq. 10).\n"
    << d.constant << " " << d.float2 << " kMultiBounceA = " << d.float2 << "(" << lit(c[0]) << ", "
    << lit(c[1]) << ");\n"
    << d.constant << " " << d.float2 << " kMultiBounceB = " << d.float2 << "(" << lit(c[2]) << ", "
    << lit(c[3]) << ");\n"
    << d.constant << " " << d.float2 << " kMultiBounceC = " << d.float2 << "(" << lit(c[4]) << ", "
    << lit(c[5]) << ");\n"
    << "// cos(alpha_s) = u^(alpha^2/2), alpha = r_p^2 (paper Eq. 26).\n"
    << d.constant << " float kConeApertureU = " << lit(in.gtso->u) << ";\n"
    << "// Texels per axis (3D x, y, z; 4D x, y, z, w; the 4D volume tiles w, kGtso4DTilesX "
       "across\n"
    << "// texture x).\n"
    << d.constant << " " << d.float3 << " kGtso3DSize = " << d.float3 << "(" << lit(t3.dims[0])
    << ", " << lit(t3.dims[1]) << ", " << lit(t3.dims[2]) << ");\n"
    << d.constant << " " << d.float4 << " kGtso4DSize = " << d.float4 << "(" << lit(t4.dims[0])
    << ", " << lit(t4.dims[1]) << ", " << lit(t4.dims[2]) << ", " << lit(t4.dims[3]) << ");\n"
    << d.constant << " float kGtso4DTilesX = " << lit(in.layout_4d.tilesX) << ";\n"
    << d.constant << " " << d.float3 << " kGtso4DVolumeSize = " << d.float3 << "("
    << lit(in.volume_4d[0]) << ", " << lit(in.volume_4d[1]) << ", " << lit(in.volume_4d[2])
    << ");\n"
    << "// Axis constants (gtso_runtime.h).\n"
    << "#define kGtsoPiF " << lit(kGtsoPi) << "\n";
  for (const GtsoAxisConstant& k : kGtsoAxisConstants)
    if (k.shaderMacro) o << "#define " << k.shaderMacro << " " << lit(k.value) << "\n";
  o << "\n"
    << closedFormConstants(in, d) << kRuntimeLookupShader
    << "\n// gtsoConeModel takes perceptual roughness rp (HDRP); this one the GGX width alpha = "
       "rp^2\n"
    << "// (Filament, XeGTAO): the same cone.\n"
    << "float gtsoConeModelFromAlpha(float A, float cosBeta, float alpha) {\n"
    << "  return gtsoConeModel(A, cosBeta, sqrt(alpha));\n}\n"
    << paperFunction() << profileFunctions(in) << profileTableFunctions(in, d) << tunedFunctions(in)
    << "\n#endif  // GTBAKE_TABLES_INCLUDED\n";
  return o.str();
}

}  // namespace gtbake
