#include <cstdio>
#include <sstream>

#include "export/generated_code.h"

namespace gtbake {
namespace {

struct Dialect {
  const char* float2;
  const char* float3;
  const char* constant;  // storage qualifier of a file-scope constant
  const char* suffix;    // float literal suffix
  const char* texture;   // parameter declaration of the volume texture
  const char* sample;    // sampling expression with %s for the coordinate
};

constexpr Dialect kHlsl = {"float2",
                           "float3",
                           "static const",
                           "f",
                           "Texture3D<float> tex, SamplerState linearClamp",
                           "tex.SampleLevel(linearClamp, %s, 0.0f)"};
constexpr Dialect kGlsl = {"vec2", "vec3",          "const",
                           "",     "sampler3D tex", "textureLod(tex, %s, 0.0).r"};

std::string lit(const Dialect& d, double v) {
  return floatLiteral(static_cast<float>(v)) + d.suffix;
}

std::string sample(const Dialect& d, const std::string& coord) {
  char buf[160];
  std::snprintf(buf, sizeof(buf), d.sample, coord.c_str());
  return buf;
}

std::string axisT(const Dialect& d, const GtsoAxis& a) {
  return "gtsoAxisT(" + quantityExpression(a.quantity, false) + ", " + lit(d, a.min) + ", " +
         lit(d, a.max) + ")";
}

}  // namespace

std::string makeShaderInclude(const GeneratedCodeInput& in, ShaderLanguage language) {
  const Dialect& d = language == ShaderLanguage::kHlsl ? kHlsl : kGlsl;
  const GtsoTable& t3 = in.gtso->table3d;
  const GtsoTable& t4 = in.gtso->table4d;
  const auto& c = in.fit->linear;
  const std::string f3 = d.float3;
  const std::string one = lit(d, 1.0), zero = lit(d, 0.0), half = lit(d, 0.5);
  std::ostringstream o;
  o << "// gtbake_tables." << (language == ShaderLanguage::kHlsl ? "hlsl" : "glsl")
    << ": GTAO multi-bounce, GTSO cone model and table lookups (include file).\n"
    << provenanceComment(in) << "// Textures: gtso3d.dds/.ktx2 (" << t3.volume[0] << "x"
    << t3.volume[1] << "x" << t3.volume[2] << ") and gtso4d.dds/.ktx2 (" << t4.volume[0] << "x"
    << t4.volume[1] << "x" << t4.volume[2]
    << "), BC4_UNORM, sampled with a linear, clamp-to-edge sampler.\n"
    << "#ifndef GTBAKE_TABLES_INCLUDED\n#define GTBAKE_TABLES_INCLUDED\n\n"
    << "// {slope, intercept}: a(rho) = x*rho + y; G = a*A^3 - b*A^2 + c*A (paper Eq. 10).\n"
    << d.constant << " " << d.float2 << " kMultiBounceA = " << d.float2 << "(" << lit(d, c[0])
    << ", " << lit(d, c[1]) << ");\n"
    << d.constant << " " << d.float2 << " kMultiBounceB = " << d.float2 << "(" << lit(d, c[2])
    << ", " << lit(d, c[3]) << ");\n"
    << d.constant << " " << d.float2 << " kMultiBounceC = " << d.float2 << "(" << lit(d, c[4])
    << ", " << lit(d, c[5]) << ");\n"
    << "// cos(alpha_s) = u^(alpha^2/2), alpha = r_p^2 (paper Eq. 26).\n"
    << d.constant << " float kConeApertureU = " << lit(d, in.gtso->u) << ";\n"
    << d.constant << " float kGtsoPi = " << lit(d, 3.14159265358979323846) << ";\n"
    << d.constant << " float kGtso4DSlices = " << lit(d, t4.dims[3]) << ";  // N_w\n"
    << d.constant << " float kGtso4DDepth = " << lit(d, t4.dims[2]) << ";   // N_z\n\n"
    << "float gtsoAxisT(float q, float qmin, float qmax) {\n"
    << "  return clamp((q - qmin) / (qmax - qmin), " << zero << ", " << one << ");\n}\n"
    << "// Half-texel remap: t = 0 and 1 land on the first and last texel centres.\n"
    << "float gtsoTexelRemap(float t, float n) { return (t * (n - " << one << ") + " << half
    << ") / n; }\n\n"
    << f3 << " gtso3DTexCoord(float A, float cosBeta, float rp) {\n"
    << "  return " << f3 << "(";
  for (int i = 0; i < 3; ++i) {
    o << (i ? ",\n                " : "") << "gtsoTexelRemap(" << axisT(d, t3.axes[i]) << ", "
      << lit(d, t3.dims[i]) << ")";
  }
  o << ");\n}\n\n"
    << "// Folded 4D volume: coordinates of slices s0 and s0 + 1 along w and the lerp weight.\n"
    << "void gtso4DTexCoord(float A, float cosBeta, float rp, float cosThetaO, out " << f3
    << " c0, out " << f3 << " c1, out float weight) {\n"
    << "  float sw = " << axisT(d, t4.axes[3]) << " * (kGtso4DSlices - " << one << ");\n"
    << "  float s0 = min(floor(sw), kGtso4DSlices - " << lit(d, 2.0) << ");\n"
    << "  weight = sw - s0;\n"
    << "  float zin = " << axisT(d, t4.axes[2]) << " * (kGtso4DDepth - " << one << ") + " << half
    << ";\n"
    << "  float u = gtsoTexelRemap(" << axisT(d, t4.axes[0]) << ", " << lit(d, t4.dims[0]) << ");\n"
    << "  float v = gtsoTexelRemap(" << axisT(d, t4.axes[1]) << ", " << lit(d, t4.dims[1]) << ");\n"
    << "  float depth = kGtso4DDepth * kGtso4DSlices;\n"
    << "  c0 = " << f3 << "(u, v, (s0 * kGtso4DDepth + zin) / depth);\n"
    << "  c1 = " << f3 << "(u, v, ((s0 + " << one << ") * kGtso4DDepth + zin) / depth);\n}\n\n"
    << "float gtso3DSample(" << d.texture << ", float A, float cosBeta, float rp) {\n"
    << "  return " << sample(d, "gtso3DTexCoord(A, cosBeta, rp)") << ";\n}\n\n"
    << "float gtso4DSample(" << d.texture
    << ", float A, float cosBeta, float rp, float cosThetaO) {\n"
    << "  " << f3 << " c0;\n  " << f3 << " c1;\n  float weight;\n"
    << "  gtso4DTexCoord(A, cosBeta, rp, cosThetaO, c0, c1, weight);\n"
    << "  return mix_lerp(" << sample(d, "c0") << ", " << sample(d, "c1") << ", weight);\n}\n\n"
    << "// Multi-bounce G(A, rho), clamped below by A as in the paper's listing.\n"
    << "float multiBounce(float A, float albedo) {\n"
    << "  float a = kMultiBounceA.x * albedo + kMultiBounceA.y;\n"
    << "  float b = kMultiBounceB.x * albedo + kMultiBounceB.y;\n"
    << "  float c = kMultiBounceC.x * albedo + kMultiBounceC.y;\n"
    << "  return max(A, ((a * A - b) * A + c) * A);\n}\n\n"
    << "// Solid angle of the intersection of two spherical caps (half-angles up to pi/2).\n"
    << "float coneCapIntersection(float alphaV, float alphaS, float beta) {\n"
    << "  if (beta >= alphaV + alphaS) return " << zero << ";\n"
    << "  if (beta <= abs(alphaV - alphaS))\n"
    << "    return " << lit(d, 2.0) << " * kGtsoPi * (" << one << " - cos(min(alphaV, alphaS)));\n"
    << "  float c1 = cos(alphaV), c2 = cos(alphaS), cd = cos(beta);\n"
    << "  float s1 = sin(alphaV), s2 = sin(alphaS), sd = sin(beta);\n"
    << "  float t0 = acos(clamp((cd - c1 * c2) / (s1 * s2), -" << one << ", " << one << "));\n"
    << "  float t1 = acos(clamp((c2 - cd * c1) / (sd * s1), -" << one << ", " << one << "));\n"
    << "  float t2 = acos(clamp((c1 - cd * c2) / (sd * s2), -" << one << ", " << one << "));\n"
    << "  return " << lit(d, 2.0) << " * (kGtsoPi - t0 - c1 * t1 - c2 * t2);\n}\n\n"
    << "// Cone-to-cone specular occlusion (paper Eq. 19), cos(alpha_s) = u^(alpha^2/2), from the "
       "GGX\n"
    << "// width alpha (Filament, XeGTAO); gtsoConeModel takes perceptual roughness (HDRP).\n"
    << "float gtsoConeModelFromAlpha(float A, float cosBeta, float alpha) {\n"
    << "  float cosS = pow(kConeApertureU, alpha * alpha * " << half << ");\n"
    << "  float alphaV = acos(sqrt(max(" << one << " - A, " << zero << ")));\n"
    << "  float beta = acos(clamp(cosBeta, -" << one << ", " << one << "));\n"
    << "  if (" << one << " - cosS < " << lit(d, 1e-7) << ") return beta <= alphaV ? " << one
    << " : " << zero << ";  // mirror limit\n"
    << "  return coneCapIntersection(alphaV, acos(cosS), beta) / (" << lit(d, 2.0)
    << " * kGtsoPi * (" << one << " - cosS));\n}\n\n"
    << "// The cone model for perceptual roughness rp (alpha = rp^2).\n"
    << "float gtsoConeModel(float A, float cosBeta, float rp) {\n"
    << "  return gtsoConeModelFromAlpha(A, cosBeta, rp * rp);\n}\n\n"
    << "#endif  // GTBAKE_TABLES_INCLUDED\n";
  std::string s = o.str();
  const std::string lerp = language == ShaderLanguage::kHlsl ? "lerp(" : "mix(";
  for (std::size_t p = s.find("mix_lerp("); p != std::string::npos; p = s.find("mix_lerp(")) {
    s.replace(p, 9, lerp);
  }
  return s;
}

}  // namespace gtbake
