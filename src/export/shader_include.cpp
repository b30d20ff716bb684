// The HLSL and GLSL includes: templates/gtbake_tables.shader.in filled with the provenance, the
// language's names and macros, the constants (from the same C++ constants the C++ lookup uses)
// and src/runtime/gtso_runtime.shader verbatim (docs/export.md §5a).
#include <cctype>
#include <cstdio>
#include <sstream>

#include "encode/bc4_layout.h"
#include "export/code_templates.h"
#include "export/generated_code.h"
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
  const char* macros;    // src/runtime/gtso_language.<name>: what gtso_runtime.shader needs
};

const Dialect kHlsl = {"hlsl", "float2", "float3", "float4", "static const", kRuntimeHlslMacros};
const Dialect kGlsl = {"glsl", "vec2", "vec3", "vec4", "const", kRuntimeGlslMacros};

// A float literal both languages read as a 32-bit float (no suffix: HLSL and GLSL both take
// "1.5" as float).
std::string lit(double v) {
  return floatLiteral(static_cast<float>(v));
}

// A constant float array: "static const float name[N] = {" (HLSL) or "const float name[N] =
// float[N](" (GLSL), the values perLine a line, each line indented by four spaces.
std::string shaderArray(const Dialect& d, const std::string& name, const std::vector<double>& v,
                        std::size_t perLine) {
  const bool hlsl = std::string(d.name) == "hlsl";
  std::ostringstream a;
  a << d.constant << " float " << name << "[" << v.size()
    << "] = " << (hlsl ? "{" : "float[" + std::to_string(v.size()) + "](");
  for (std::size_t i = 0; i < v.size(); ++i)
    a << (i ? "," : "") << (i % perLine == 0 ? "\n    " : " ") << lit(v[i]);
  a << (hlsl ? "};\n" : ");\n");
  return a.str();
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// `name`(A, albedo): Equation 10 with the constants c (multibounce.shader.in).
std::string multiBounceFunction(const std::string& name, const std::array<double, 6>& c) {
  return fillTemplate(kMultiBounceShaderTemplate, {{"NAME", name},
                                                   {"A1", lit(c[0])},
                                                   {"A0", lit(c[1])},
                                                   {"B1", lit(c[2])},
                                                   {"B0", lit(c[3])},
                                                   {"C1", lit(c[4])},
                                                   {"C0", lit(c[5])}});
}

// One function per engine profile (docs/profiles.md), after the runtime template.
std::string profileFunctions(const GeneratedCodeInput& in) {
  if (in.profiles == nullptr || in.profiles->empty()) return "";
  std::string o = "\n" + profileGateComment(*in.profiles);
  if (shippedProfileCount(*in.profiles) == 0) return o;
  o += "// Engine profiles (docs/profiles.md): Equation 10 refitted on the A each screen-space\n"
       "// estimator computes. RMSE of G on that A: paper's constants | profile held out by "
       "scene.\n";
  for (const ProfileInput& p : *in.profiles) {
    if (!p.gate.shipped) continue;
    o += "// " + p.estimator + ": " + lit(p.rmse_paper) + " | " + lit(p.rmse_held_out) + "\n" +
         multiBounceFunction("multiBounce_" + profileIdentifier(p.estimator), p.linear);
  }
  return o;
}

// The profile tables (docs/profiles.md §8): every shipped table's albedos and values in two
// arrays, the one lookup of src/runtime/multibounce_table.shader, and per table
// multiBounceTable_<estimator>(A, albedo) naming its place in the arrays.
std::string profileTableFunctions(const GeneratedCodeInput& in, const Dialect& d) {
  if (in.profiles == nullptr) return "";
  std::vector<double> rhos, values;
  std::string functions;
  for (const ProfileInput& p : *in.profiles) {
    if (!p.gate.shipped || p.table_nodes == 0) continue;
    functions += fillTemplate(kMultiBounceTableShaderTemplate,
                              {{"ESTIMATOR", p.estimator},
                               {"RMSE_HELD_OUT", lit(p.table_held_out_rmse)},
                               {"ID", profileIdentifier(p.estimator)},
                               {"RHO_OFFSET", std::to_string(rhos.size())},
                               {"ROWS", std::to_string(p.table_rhos.size())},
                               {"VALUES_OFFSET", std::to_string(values.size())},
                               {"NODES", std::to_string(p.table_nodes)}});
    rhos.insert(rhos.end(), p.table_rhos.begin(), p.table_rhos.end());
    values.insert(values.end(), p.table_values.begin(), p.table_values.end());
  }
  if (functions.empty()) return "";
  return fillTemplate(kProfileTablesShaderTemplate,
                      {{"RHO_ARRAY", shaderArray(d, "kMultiBounceTableRho", rhos, 8)},
                       {"VALUES_ARRAY", shaderArray(d, "kMultiBounceTableValues", values, 8)},
                       {"LOOKUP", kRuntimeTableShader},
                       {"FUNCTIONS", functions}});
}

// One constant and one Equation 10 function per tuned setting (docs/tune.md).
std::string tunedFunctions(const GeneratedCodeInput& in) {
  if (in.tuned == nullptr || in.tuned->empty()) return "";
  std::ostringstream o;
  o << "\n// Tuned settings (docs/tune.md; gtbake_tables.h kTunedSettings has the intervals): the\n"
    << "// evaluated value with the lowest RMSE of G under the profile refit, and that refit.\n";
  for (const TunedSettingInput& t : *in.tuned) {
    const std::string id = profileIdentifier(t.estimator) + "_" + t.setting;
    o << "// " << t.estimator << " " << t.setting << ": default " << lit(t.default_value)
      << ", best with the paper's constants " << lit(t.paper_best) << ", with the refit "
      << lit(t.profile_best) << " [" << lit(t.profile_low) << ", " << lit(t.profile_high) << "]"
      << (t.at_bound ? " (at the grid's end)" : "") << "; RMSE of G held out "
      << lit(t.rmse_held_out) << "\n"
      << "#define GTBAKE_TUNED_" << upper(id) << " " << lit(t.grid_value) << "\n"
      << multiBounceFunction("multiBounce_" + id, t.linear);
  }
  return o.str();
}

// The axis constants of gtso_runtime.h as shader macros.
std::string axisMacros() {
  std::string o;
  for (const GtsoAxisConstant& k : kGtsoAxisConstants)
    if (k.shaderMacro) o += "#define " + std::string(k.shaderMacro) + " " + lit(k.value) + "\n";
  return o;
}

// "x, y, z" of float literals.
template <class T>
std::string litList(const T* values, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += (i ? ", " : "") + lit(values[i]);
  return s;
}

// The placeholders of gtbake_tables.shader.in that name the language's types and qualifiers.
TemplateValues dialectValues(const Dialect& d) {
  return {{"LANGUAGE", d.name}, {"LANGUAGE_MACROS", d.macros}, {"CONST", d.constant},
          {"FLOAT2", d.float2}, {"FLOAT3", d.float3},          {"FLOAT4", d.float4}};
}

// The placeholders of gtbake_tables.shader.in that hold fit's, gtso's and encode's numbers.
TemplateValues constantValues(const GeneratedCodeInput& in) {
  const auto& c = in.fit->linear;
  const auto extent = [](const std::array<int, 3>& v) {
    return std::to_string(v[0]) + "x" + std::to_string(v[1]) + "x" + std::to_string(v[2]);
  };
  return {{"VOLUME_3D", extent(in.volume_3d)},
          {"VOLUME_4D", extent(in.volume_4d)},
          {"LAYOUT_3D", layoutSwizzle(in.layout_3d)},
          {"LAYOUT_4D", layoutSwizzle(in.layout_4d)},
          {"A1", lit(c[0])},
          {"A0", lit(c[1])},
          {"B1", lit(c[2])},
          {"B0", lit(c[3])},
          {"C1", lit(c[4])},
          {"C0", lit(c[5])},
          {"CONE_U", lit(in.gtso->u)},
          {"SIZE_3D", litList(in.gtso->table3d.dims.data(), 3)},
          {"SIZE_4D", litList(in.gtso->table4d.dims.data(), 4)},
          {"TILES_X", lit(in.layout_4d.tilesX)},
          {"VOLUME_SIZE_4D", litList(in.volume_4d.data(), 3)},
          {"PI", lit(kGtsoPi)},
          {"AXIS_MACROS", axisMacros()},
          {"CLOSED_FORM_SETS", std::to_string(kGtsoS3ClosedFormSets)},
          {"CLOSED_FORM_BASIS", std::to_string(kGtsoS3ClosedFormBasis)},
          {"CLOSED_FORM_ALPHA_FLOOR", lit(kGtsoS3ClosedFormAlphaFloor)}};
}

}  // namespace

std::string makeShaderInclude(const GeneratedCodeInput& in, ShaderLanguage language) {
  const Dialect& d = language == ShaderLanguage::kHlsl ? kHlsl : kGlsl;
  TemplateValues values = dialectValues(d);
  const TemplateValues constants = constantValues(in);
  values.insert(values.end(), constants.begin(), constants.end());
  const TemplateValues sections = {
      {"PROVENANCE", provenanceComment(in)},
      {"CLOSED_FORM_ARRAY",
       shaderArray(d, "kGtsoS3ClosedForm", in.gtso->s3_closed_form, kGtsoS3ClosedFormBasis)},
      {"RUNTIME", kRuntimeLookupShader},
      {"PAPER_FUNCTION", multiBounceFunction("multiBouncePaper", kPaperCoeffs)},
      {"PROFILES", profileFunctions(in)},
      {"PROFILE_TABLES", profileTableFunctions(in, d)},
      {"TUNED_SETTINGS", tunedFunctions(in)}};
  values.insert(values.end(), sections.begin(), sections.end());
  return fillTemplate(kShaderIncludeTemplate, values);
}

}  // namespace gtbake
