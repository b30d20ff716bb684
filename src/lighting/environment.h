// Distant lighting for gtbake lighting (docs/lighting.md §2): an environment's radiance L(ω) as
// its L2 spherical-harmonic projection (common/spherical_harmonics.h), from an equirectangular
// HDR EXR or one of the built-in analytic classes.
//
// Equirectangular convention (docs/lighting.md §2): width = 2 × height; pixel (i, j), j = 0 the
// top row, covers the polar angles θ ∈ [πj/H, π(j+1)/H] from +y (world up, glTF's frame) and the
// azimuths φ ∈ [2πi/W − π, 2π(i+1)/W − π], direction (sinθ cosφ, cosθ, sinθ sinφ) (three.js's
// equirectangular mapping). The radiance is constant over a pixel, and each pixel's SH integral
// is exact (closed-form integrals of the degree-≤2 monomials over the pixel's patch), so a
// constant map projects to L_0 alone up to rounding.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "common/spherical_harmonics.h"

namespace gtbake {

struct Environment {
  std::string name;  // the class name or the file's stem
  ShVector sh{};     // radiance coefficients L_i = ∫ L Y_i dω
};

// Radiance samples of an equirectangular map: width = 2 × height, row-major, row 0 at the top.
struct EquirectMap {
  int width = 0;
  int height = 0;
  std::vector<double> radiance;
};

// ∫ L Y_i dω of a map with pixel-constant radiance (exact per pixel, see above). Throws a one-line
// gtbake::Error when the map is not 2:1, empty, or holds a negative or non-finite value.
ShVector projectEquirect(const EquirectMap& map, const std::string& where);

// Reads an equirectangular EXR: luminance 0.2126 R + 0.7152 G + 0.0722 B of its R, G, B channels
// (or its Y channel alone), negative luminance (lossy encodings leave some) read as 0. One-line
// gtbake::Error if unreadable, without those channels or holding a non-finite value (and, from
// projectEquirect, if not 2:1).
EquirectMap decodeEnvironmentExr(const std::string& bytes, const std::string& name);
// The file's environment scaled like the built-in classes (an open floor receives G = 1); one
// that sends no light to an open floor is a one-line error.
Environment readEnvironment(const std::filesystem::path& path);

// The built-in classes (docs/lighting.md §2), each scaled so an open floor (normal +y) receives
// G = 1 (irradiance/π of the L2 projection):
//   uniform   L = 1
//   overcast  L ∝ (1 + 2 max(0, y))/3 (CIE-overcast-like, zenith three times the horizon)
//   horizon   L ∝ 1 + 2(1 − |y|) (bright horizon, dim zenith and nadir)
//   sun-sky   the uniform sky plus a sun disk of 2.5° radius at 45° elevation towards +x giving
//             three times the sky's floor irradiance
//   window    L = 1 for x > 0, 0 behind (a one-sided opening)
const std::vector<std::string>& environmentClasses();
Environment builtInEnvironment(const std::string& name);

// An argument of --env: a built-in class name or an EXR file.
Environment environmentFromArgument(const std::string& argument);

// (1/π) ∫ L(ω) max(0, n·ω) dω: the unoccluded irradiance over π at the unit normal n, from the
// L2 coefficients (Funk–Hecke, docs/lighting.md §1).
double openIrradiance(const ShVector& sh, double nx, double ny, double nz);

}  // namespace gtbake
