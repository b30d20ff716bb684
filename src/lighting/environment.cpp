#include "lighting/environment.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/math_constants.h"

namespace gtbake {

namespace {

// Monomials of the unit direction integrated over a patch, in the order
// 1, x, y, z, xy, yz, xz, xx, yy, zz (docs/lighting.md §2).
constexpr int kMonomials = 10;

// Primitives in μ = cos θ (s = √(1 − μ²)) of 1, s, μ, μs, s², μ².
void muPrimitives(double mu, double* f) {
  const double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
  f[0] = mu;
  f[1] = 0.5 * (mu * s + std::asin(mu));
  f[2] = 0.5 * mu * mu;
  f[3] = -(s * s * s) / 3.0;
  f[4] = mu - mu * mu * mu / 3.0;
  f[5] = mu * mu * mu / 3.0;
}

// Primitives in φ of 1, cos φ, sin φ, cos φ sin φ, cos² φ, sin² φ.
void phiPrimitives(double phi, double* f) {
  const double c = std::cos(phi);
  const double s = std::sin(phi);
  f[0] = phi;
  f[1] = s;
  f[2] = -c;
  f[3] = 0.5 * s * s;
  f[4] = 0.5 * phi + 0.5 * s * c;
  f[5] = 0.5 * phi - 0.5 * s * c;
}

// Row j's μ integrals (from μ(j + 1) up to μ(j)) and column i's φ integrals.
std::vector<double> rowIntegrals(int height) {
  std::vector<double> rows(6 * static_cast<std::size_t>(height));
  double top[6];
  double bottom[6];
  muPrimitives(1.0, top);
  for (int j = 0; j < height; ++j) {
    muPrimitives(j + 1 == height ? -1.0 : std::cos(kPi * (j + 1) / height), bottom);
    for (int m = 0; m < 6; ++m) rows[6 * j + m] = top[m] - bottom[m];
    std::copy(bottom, bottom + 6, top);
  }
  return rows;
}

std::vector<double> columnIntegrals(int width) {
  std::vector<double> columns(6 * static_cast<std::size_t>(width));
  double left[6];
  double right[6];
  phiPrimitives(-kPi, left);
  for (int i = 0; i < width; ++i) {
    phiPrimitives(2.0 * kPi * (i + 1) / width - kPi, right);
    for (int m = 0; m < 6; ++m) columns[6 * i + m] = right[m] - left[m];
    std::copy(right, right + 6, left);
  }
  return columns;
}

// The monomial integrals of one pixel from its row's and column's factors.
void pixelMonomials(const double* r, const double* c, double* out) {
  out[0] = r[0] * c[0];  // 1
  out[1] = r[1] * c[1];  // x = s cos φ
  out[2] = r[2] * c[0];  // y = μ
  out[3] = r[1] * c[2];  // z = s sin φ
  out[4] = r[3] * c[1];  // xy
  out[5] = r[3] * c[2];  // yz
  out[6] = r[4] * c[3];  // xz
  out[7] = r[4] * c[4];  // xx
  out[8] = r[5] * c[0];  // yy
  out[9] = r[4] * c[5];  // zz
}

// The SH coefficients from the monomial integrals (common/spherical_harmonics.h's basis).
ShVector shFromMonomials(const double* m) {
  constexpr double c0 = 0.28209479177387814;
  constexpr double c1 = 0.48860251190291992;
  constexpr double c2 = 1.0925484305920792;
  constexpr double c3 = 0.31539156525252005;
  constexpr double c4 = 0.54627421529603959;
  return {c0 * m[0],
          c1 * m[2],
          c1 * m[3],
          c1 * m[1],
          c2 * m[4],
          c2 * m[5],
          c3 * (3.0 * m[9] - m[0]),
          c2 * m[6],
          c4 * (m[7] - m[8])};
}

// A map of `function` at pixel centres.
EquirectMap rasterize(const std::function<double(double, double, double)>& function) {
  EquirectMap map;
  map.height = 512;
  map.width = 1024;
  map.radiance.resize(static_cast<std::size_t>(map.width) * map.height);
  for (int j = 0; j < map.height; ++j) {
    const double theta = kPi * (j + 0.5) / map.height;
    for (int i = 0; i < map.width; ++i) {
      const double phi = 2.0 * kPi * (i + 0.5) / map.width - kPi;
      map.radiance[static_cast<std::size_t>(j) * map.width + i] = function(
          std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
    }
  }
  return map;
}

ShVector scaled(const ShVector& sh, double factor) {
  ShVector out;
  for (int i = 0; i < kShCoefficients; ++i) out[i] = sh[i] * factor;
  return out;
}

// Scaled so that an open floor (normal +y) has G = 1.
Environment normalised(const std::string& name, const ShVector& sh) {
  return {name, scaled(sh, 1.0 / openIrradiance(sh, 0.0, 1.0, 0.0))};
}

ShVector sunAndSky(const std::string& where) {
  const ShVector sky =
      projectEquirect(rasterize([](double, double, double) { return 1.0; }), where);
  const double c = std::cos(kPi / 4.0);
  const double cos_radius = std::cos(2.5 * kPi / 180.0);
  const ShVector sun = projectEquirect(rasterize([&](double x, double y, double) {
                                         return x * c + y * c >= cos_radius ? 1.0 : 0.0;
                                       }),
                                       where);
  const double factor = 3.0 * openIrradiance(sky, 0, 1, 0) / openIrradiance(sun, 0, 1, 0);
  ShVector out;
  for (int i = 0; i < kShCoefficients; ++i) out[i] = sky[i] + factor * sun[i];
  return out;
}

}  // namespace

ShVector projectEquirect(const EquirectMap& map, const std::string& where) {
  if (map.height < 1 || map.width != 2 * map.height) {
    throw Error(where + ": an equirectangular environment must be twice as wide as high, got " +
                std::to_string(map.width) + "x" + std::to_string(map.height));
  }
  const std::vector<double> rows = rowIntegrals(map.height);
  const std::vector<double> columns = columnIntegrals(map.width);
  double sums[kMonomials] = {};
  for (int j = 0; j < map.height; ++j) {
    for (int i = 0; i < map.width; ++i) {
      const double value = map.radiance[static_cast<std::size_t>(j) * map.width + i];
      if (!std::isfinite(value) || value < 0.0) {
        throw Error(where + ": radiance at pixel (" + std::to_string(i) + ", " + std::to_string(j) +
                    ") is negative or not finite");
      }
      double m[kMonomials];
      pixelMonomials(&rows[6 * j], &columns[6 * i], m);
      for (int k = 0; k < kMonomials; ++k) sums[k] += value * m[k];
    }
  }
  return shFromMonomials(sums);
}

EquirectMap decodeEnvironmentExr(const std::string& bytes, const std::string& name) {
  const ExrImage image = decodeExr(bytes, name);
  EquirectMap map;
  map.width = image.width;
  map.height = image.height;
  const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
  map.radiance.assign(pixels, 0.0);
  const bool rgb =
      image.channels.count("R") && image.channels.count("G") && image.channels.count("B");
  if (!rgb && !image.channels.count("Y"))
    throw Error(name + ": an environment EXR needs R, G and B channels or a Y channel");
  const char* names[3] = {"R", "G", "B"};
  const double weights[3] = {0.2126, 0.7152, 0.0722};  // Rec. 709 luminance
  for (int c = 0; c < (rgb ? 3 : 1); ++c) {
    const std::vector<float>& values = image.channel(rgb ? names[c] : "Y", name);
    for (std::size_t p = 0; p < pixels; ++p) {
      if (!std::isfinite(values[p])) {
        throw Error(name + ": pixel (" + std::to_string(p % image.width) + ", " +
                    std::to_string(p / image.width) + ") is not finite");
      }
      map.radiance[p] += (rgb ? weights[c] : 1.0) * values[p];
    }
  }
  // Lossy HDR encodings leave tiny negative values (Blender's studio lights hold some): read as 0.
  for (double& v : map.radiance) v = std::max(0.0, v);
  return map;
}

Environment readEnvironment(const std::filesystem::path& path) {
  const std::string where = path.string();
  const ShVector sh = projectEquirect(decodeEnvironmentExr(readFile(path), where), where);
  if (!(openIrradiance(sh, 0.0, 1.0, 0.0) > 0.0)) {
    throw Error(where + ": the environment sends no light to an open floor (normal +y)");
  }
  return normalised(path.stem().string(), sh);
}

const std::vector<std::string>& environmentClasses() {
  static const std::vector<std::string> names = {"uniform", "overcast", "horizon", "sun-sky",
                                                 "window"};
  return names;
}

Environment builtInEnvironment(const std::string& name) {
  const std::string where = "environment " + name;
  if (name == "uniform")
    return normalised(
        name, projectEquirect(rasterize([](double, double, double) { return 1.0; }), where));
  if (name == "overcast") {
    return normalised(name, projectEquirect(rasterize([](double, double y, double) {
                                              return (1.0 + 2.0 * std::max(0.0, y)) / 3.0;
                                            }),
                                            where));
  }
  if (name == "horizon") {
    return normalised(name, projectEquirect(rasterize([](double, double y, double) {
                                              return 1.0 + 2.0 * (1.0 - std::abs(y));
                                            }),
                                            where));
  }
  if (name == "sun-sky") return normalised(name, sunAndSky(where));
  if (name == "window") {
    return normalised(
        name, projectEquirect(
                  rasterize([](double x, double, double) { return x > 0.0 ? 1.0 : 0.0; }), where));
  }
  throw Error("unknown environment class '" + name +
              "' (uniform, overcast, horizon, sun-sky, window)");
}

Environment environmentFromArgument(const std::string& argument) {
  for (const std::string& name : environmentClasses()) {
    if (argument == name) return builtInEnvironment(name);
  }
  return readEnvironment(argument);
}

double openIrradiance(const ShVector& sh, double nx, double ny, double nz) {
  double basis[kShCoefficients];
  shBasis(nx, ny, nz, basis);
  double sum = 0.0;
  for (int i = 0; i < kShCoefficients; ++i) sum += clampedCosineBand(shBand(i)) * sh[i] * basis[i];
  return sum / kPi;
}

}  // namespace gtbake
