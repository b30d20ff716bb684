// The C++ header: templates/gtbake_tables.h.in and its sections filled with the provenance, the
// constants, the BC4 blocks and src/runtime/gtso_runtime.h verbatim (docs/export.md §5a).
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "common/error.h"
#include "encode/bc4_layout.h"
#include "export/code_templates.h"
#include "export/generated_code.h"
#include "fit/multibounce_coeffs.h"
#include "gtso/gtso_tables.h"
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

// "kGtso3DBC4[2048] = {...};" and its static_assert: the blocks as little-endian uint64 literals.
std::string blocksArray(const char* name, const Bc4Volume& volume) {
  std::ostringstream o;
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
  return o.str();
}

// "a, b, c" of the values.
template <class T, class Format>
std::string joined(const T& values, Format format) {
  std::string s;
  for (const auto& v : values) s += (s.empty() ? "" : ", ") + format(v);
  return s;
}
std::string intList(const int* values, int n) {
  return joined(std::vector<int>(values, values + n), [](int v) { return std::to_string(v); });
}

// Equation 10's six coefficients as the placeholders A1, A0, B1, B0, C1, C0 (float literals).
TemplateValues coeffValues(const std::string& prefix, const std::array<double, 6>& c) {
  const char* names[6] = {"A1", "A0", "B1", "B0", "C1", "C0"};
  TemplateValues values;
  for (int i = 0; i < 6; ++i) values.emplace_back(prefix + names[i], f(float(c[i])));
  return values;
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
         std::to_string(nz) + " texels (" + gtso::axisName(gtso::tableAxis(4, 3)) +
         " slice w at x = " + std::to_string(nx) + " (w mod " + std::to_string(l.tilesX) +
         "), z = " + std::to_string(nz) + " floor(w / " + std::to_string(l.tilesX) + "))";
}

// "texture x = theta_o, y = r_p, z = A" for a layout.
std::string layoutText(int dims, const GtsoLayout& l) {
  const auto name = [&](int axis) { return gtso::axisName(gtso::tableAxis(dims, axis)); };
  return std::string("x = ") + name(l.axis[0]) + ", y = " + name(l.axis[1]) +
         ", z = " + name(l.axis[2]);
}

// The placeholders of gtbake_tables.h.in that hold fit's, gtso's and encode's numbers.
TemplateValues constantValues(const GeneratedCodeInput& in) {
  const GtsoLayout &l3 = in.layout_3d, &l4 = in.layout_4d;
  TemplateValues v = coeffValues("", in.fit->linear);
  for (auto& paper : coeffValues("PAPER_", kPaperCoeffs)) v.push_back(std::move(paper));
  const TemplateValues rest = {{"VERSION", in.version},
                               {"CONE_U", f(float(in.gtso->u))},
                               {"CONE_U_SE", f(float(in.gtso->u_se))},
                               {"SIZE_3D", intList(in.gtso->table3d.dims.data(), 3)},
                               {"SIZE_4D", intList(in.gtso->table4d.dims.data(), 4)},
                               {"LAYOUT_TEXT_3D", layoutText(3, l3)},
                               {"LAYOUT_TEXT_4D", layoutText(4, l4)},
                               {"TILING_TEXT", tilingText(in)},
                               {"LAYOUT_AXES_3D", intList(l3.axis, 3)},
                               {"LAYOUT_AXES_4D", intList(l4.axis, 3)},
                               {"TILES_X", std::to_string(l4.tilesX)},
                               {"VOLUME_3D", intList(in.volume_3d.data(), 3)},
                               {"VOLUME_4D", intList(in.volume_4d.data(), 3)},
                               {"BC4_MAX_3D", f(float(in.bc4_3d->max_abs))},
                               {"BC4_RMSE_3D", f(float(in.bc4_3d->rmse))},
                               {"BC4_MAX_4D", f(float(in.bc4_4d->max_abs))},
                               {"BC4_RMSE_4D", f(float(in.bc4_4d->rmse))},
                               {"BLOCKS_3D", blocksArray("kGtso3DBC4", *in.bc4_3d)},
                               {"BLOCKS_4D", blocksArray("kGtso4DBC4", *in.bc4_4d)}};
  v.insert(v.end(), rest.begin(), rest.end());
  return v;
}

// "{a1, a0}, {b1, b0}, {c1, c0}" of a profile's or tuned setting's struct row.
std::string coeffPairs(const std::array<double, 6>& c) {
  return "{" + f(float(c[0])) + ", " + f(float(c[1])) + "}, {" + f(float(c[2])) + ", " +
         f(float(c[3])) + "}, {" + f(float(c[4])) + ", " + f(float(c[5])) + "}";
}

// The engine profiles (docs/profiles.md): Equation 10 refitted on each estimator's Â.
std::string profilesSection(const GeneratedCodeInput& in) {
  if (in.profiles == nullptr || in.profiles->empty()) return "";
  const std::size_t shipped = shippedProfileCount(*in.profiles);
  if (shipped == 0) return profileGateComment(*in.profiles);
  std::string rows;
  for (const ProfileInput& p : *in.profiles) {
    if (!p.gate.shipped) continue;
    rows += "    {\"" + p.estimator + "\", " + coeffPairs(p.linear) + ", " +
            f(float(p.rmse_paper)) + ", " + f(float(p.rmse_held_out)) + ", " +
            f(float(p.band_max)) + "},\n";
  }
  return profileGateComment(*in.profiles) +
         fillTemplate(kProfilesHeaderTemplate,
                      {{"PROFILE_COUNT", std::to_string(shipped)}, {"PROFILE_ROWS", rows}});
}

// The monotone 2D tables shipped beside the cubic of the profiles whose cubic is not adequate
// (docs/profiles.md §8), as arrays and one bilinear lookup; only for shipped profiles.
std::string profileTablesSection(const GeneratedCodeInput& in) {
  if (in.profiles == nullptr) return "";
  std::ostringstream arrays, list;
  std::size_t count = 0;
  for (const ProfileInput& p : *in.profiles) {
    if (!p.gate.shipped || p.table_nodes == 0) continue;
    ++count;
    const std::string id = profileIdentifier(p.estimator);
    arrays << "inline constexpr float kMultiBounceTableRho_" << id << "[" << p.table_rhos.size()
           << "] = {" << joined(p.table_rhos, [](double r) { return f(float(r)); })
           << "};\ninline constexpr float kMultiBounceTableValues_" << id << "["
           << p.table_values.size() << "] = {";
    for (std::size_t i = 0; i < p.table_values.size(); ++i)
      arrays << (i % 8 == 0 ? "\n    " : " ") << f(float(p.table_values[i])) << ",";
    arrays << "};\n";
    list << "    {\"" << p.estimator << "\", " << p.table_nodes << ", " << p.table_rhos.size()
         << ", kMultiBounceTableRho_" << id << ", kMultiBounceTableValues_" << id << ", "
         << f(float(p.table_held_out_rmse)) << "},\n";
  }
  const std::string declaration =
      count == 0 ? ""
                 : "inline constexpr GtbakeMultiBounceTable kMultiBounceTables[" +
                       std::to_string(count) + "] = {\n" + list.str() + "};\n";
  return fillTemplate(kProfileTablesHeaderTemplate, {{"TABLE_COUNT", std::to_string(count)},
                                                     {"TABLE_ARRAYS", arrays.str()},
                                                     {"TABLE_LIST", declaration}});
}

// The tuned settings (docs/tune.md), each with the profile refitted where it was evaluated.
std::string tunedSettingsSection(const GeneratedCodeInput& in) {
  if (in.tuned == nullptr || in.tuned->empty()) return "";
  std::string rows;
  for (const TunedSettingInput& t : *in.tuned) {
    rows += "    {\"" + t.estimator + "\", \"" + t.setting + "\", " + f(float(t.default_value)) +
            ", " + f(float(t.paper_best)) + ", " + f(float(t.profile_best)) + ", " +
            f(float(t.profile_low)) + ", " + f(float(t.profile_high)) + ", " +
            (t.at_bound ? "true" : "false") + ", " + f(float(t.grid_value)) + ", " +
            coeffPairs(t.linear) + ", " + f(float(t.rmse_held_out)) + "},\n";
  }
  return fillTemplate(kTunedSettingsHeaderTemplate,
                      {{"TUNED_COUNT", std::to_string(in.tuned->size())}, {"TUNED_ROWS", rows}});
}

// The closed-form S3 (gtso.json closed_form): its coefficients and errors for the template's
// physical-input entry point over gtsoS3ClosedForm of gtso_runtime.h.
TemplateValues closedFormValues(const GeneratedCodeInput& in) {
  const nlohmann::json& j = in.gtso->json;
  std::string coeffs;
  for (std::size_t i = 0; i < in.gtso->s3_closed_form.size(); ++i) {
    coeffs += (i % kGtsoS3ClosedFormBasis == 0 ? "\n    " : " ") +
              f(static_cast<float>(in.gtso->s3_closed_form[i])) + ",";
  }
  const auto error = [&](const char* range, const char* stat) {
    return jsonAt(j, {"closed_form", "test", "errors", range, stat});
  };
  return {{"CLOSED_FORM_SETS", std::to_string(kGtsoS3ClosedFormSets)},
          {"CLOSED_FORM_BASIS", std::to_string(kGtsoS3ClosedFormBasis)},
          {"CLOSED_FORM_HIGH_MAX", error("r_p_ge_0.1", "max")},
          {"CLOSED_FORM_HIGH_RMS", error("r_p_ge_0.1", "rms")},
          {"CLOSED_FORM_LOW_MAX", error("r_p_lt_0.1", "max")},
          {"CLOSED_FORM_LOW_RMS", error("r_p_lt_0.1", "rms")},
          {"CLOSED_FORM_ALU", kGtsoS3ClosedFormAlu},
          {"CLOSED_FORM_COEFFS", std::to_string(kGtsoS3ClosedFormCoeffs)},
          {"CLOSED_FORM_VALUES", coeffs}};
}

}  // namespace

std::string floatLiteral(float value) {
  // The readers bound every shipped number (fit/fit_set.cpp, tune/tune_set.cpp); this keeps the
  // header compiling.
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
  TemplateValues values = constantValues(in);
  const TemplateValues closed_form = closedFormValues(in);
  values.insert(values.end(), closed_form.begin(), closed_form.end());
  const TemplateValues sections = {{"PROVENANCE", provenanceComment(in)},
                                   {"RUNTIME", kRuntimeLookupHeader},
                                   {"PROFILES", profilesSection(in)},
                                   {"PROFILE_TABLES", profileTablesSection(in)},
                                   {"TUNED_SETTINGS", tunedSettingsSection(in)}};
  values.insert(values.end(), sections.begin(), sections.end());
  return fillTemplate(kTablesHeaderTemplate, values);
}

}  // namespace gtbake
