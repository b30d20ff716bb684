// The generated C++ header (gtbake_tables.h) and shader includes (gtbake_tables.hlsl/.glsl).
//
// Conventions shared by all three (docs/export.md "Header contents"):
// - Multi-bounce (paper Eq. 10): a(ρ) = a1·ρ + a0 etc., G(A, ρ) = a·A³ − b·A² + c·A, returned as
//   max(A, G) like the paper's listing. Arrays are {slope, intercept}.
// - Axis i of a table with N texels is linear in its quantity q between min (texel 0) and max
//   (texel N − 1): t = saturate((q − min)/(max − min)), texture coordinate u = (t·(N − 1) + 0.5)/N.
// - 4D: the w axis is folded into z (z_texel = w_slice·N_z + z_texel); a lookup fetches slices
//   ⌊t_w·(N_w − 1)⌋ and the next one with trilinear filtering and lerps between them.
// - Cone model (paper Eq. 19, App. B): S = Ω∩(αv, αs, β) / (2π(1 − cos αs)), cos αv = √(1 − A),
//   cos αs = u^(α²/2), α = r_p².
#pragma once

#include <string>

#include "export/bc4_encoder.h"
#include "export/export_inputs.h"

namespace gtbake {

struct GeneratedCodeInput {
  const FitInput* fit = nullptr;
  const GtsoInput* gtso = nullptr;
  const Bc4Volume* bc4_3d = nullptr;
  const Bc4Volume* bc4_4d = nullptr;
  std::string command_line;
  std::string version;
};

enum class ShaderLanguage { kHlsl, kGlsl };

std::string makeTablesHeader(const GeneratedCodeInput& in);
std::string makeShaderInclude(const GeneratedCodeInput& in, ShaderLanguage language);

// Shortest round-trip float literal: "%.9g" of the float, with a ".0" when it has no point or
// exponent, so strtof gives back the same float.
std::string floatLiteral(float value);

// How a table axis quantity is computed from the lookup inputs (A, cosBeta, rp, cosThetaO) in
// the target language ("std::" math for C++).
std::string quantityExpression(const std::string& quantity, bool cpp);

// The shared "// ..." provenance lines: command line, versions, samples, errors.
std::string provenanceComment(const GeneratedCodeInput& in);

}  // namespace gtbake
