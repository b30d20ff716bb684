// The generated C++ header (gtbake_tables.h) and shader includes (gtbake_tables.hlsl/.glsl).
//
// All three are the templates of src/export/templates/ filled with data (docs/export.md §5a),
// carrying the runtime sources of src/runtime/ verbatim (gtso_runtime.h for C++,
// gtso_runtime.shader for HLSL/GLSL) after the provenance and the data: multi-bounce
// coefficients (paper Eq. 10, {slope, intercept}), the cone constant u, the table sizes and, in
// C++, the BC4 blocks. docs/export.md "Header contents".
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fit/fit_set.h"
#include "gtso/gtso_set.h"
#include "runtime/gtso_runtime.h"
#include "texture/bc4_encoder.h"
#include "tune/tune_set.h"

namespace gtbake {

struct GeneratedCodeInput {
  const FitInput* fit = nullptr;
  const GtsoInput* gtso = nullptr;
  const Bc4Volume* bc4_3d = nullptr;
  const Bc4Volume* bc4_4d = nullptr;
  const std::vector<ProfileInput>* profiles = nullptr;    // engine profiles (none: no table)
  const std::vector<TunedSettingInput>* tuned = nullptr;  // tuned settings (none: no table)
  // The texture layouts export chose (bc4_layout.h) and the volumes' extents in them.
  GtsoLayout layout_3d = kGtsoIdentityLayout, layout_4d = kGtsoIdentityLayout;
  std::array<int, 3> volume_3d{}, volume_4d{};
  // encode.json end_to_end (format_errors.h): every texel format's end-to-end error as shipped
  // and the recommended format per table; null: "n/a" in the provenance.
  nlohmann::json end_to_end;
  std::string command_line;
  std::string version;
};

enum class ShaderLanguage { kHlsl, kGlsl };

std::string makeTablesHeader(const GeneratedCodeInput& in);
std::string makeShaderInclude(const GeneratedCodeInput& in, ShaderLanguage language);

// Shortest round-trip float literal: "%.9g" of the float, with a ".0" when it has no point or
// exponent, so strtof gives back the same float.
std::string floatLiteral(float value);

// A profile's estimator as an identifier suffix ("gtao-runtime" -> "gtao_runtime").
std::string profileIdentifier(const std::string& estimator);
// The shipping gate's outcome per profile as comment lines (docs/profiles.md §9), and how many
// profiles passed it.
std::string profileGateComment(const std::vector<ProfileInput>& profiles);
std::size_t shippedProfileCount(const std::vector<ProfileInput>& profiles);

// The shared "// ..." provenance lines: command line, versions, samples, errors.
std::string provenanceComment(const GeneratedCodeInput& in);

}  // namespace gtbake
