// The seven classic scene types of docs/scenes.md, parameterised (procedural_scenes.h). Dimensions,
// cameras and the reasons behind them are in docs/scenes.md; every size here is in metres.
#include <Eigen/Geometry>
#include <cmath>

#include "common/error.h"
#include "common/math_constants.h"
#include "common/rng.h"
#include "scene/holed_ground.h"
#include "scene/mesh_builder.h"
#include "scene/procedural_scenes.h"

namespace gtbake {
namespace {

// Random streams of the seeded generators (one per scene type, so they never share draws).
constexpr std::uint64_t kClutterStream = 0x636c7574;  // "clut"
constexpr std::uint64_t kTerrainStream = 0x74657272;  // "terr"

const Eigen::Vector3d kUp = Eigen::Vector3d::UnitY();

// Perlin gradient noise in [−1, 1]-ish: unit gradients at integer lattice points drawn from the
// counter-based RNG (key: seed and octave; counter: the lattice point), quintic fade.
double gradientNoise(const CounterRng& rng, double x, double z) {
  const double fx = std::floor(x), fz = std::floor(z);
  const auto ix = static_cast<std::int64_t>(fx), iz = static_cast<std::int64_t>(fz);
  const auto dotGradient = [&](std::int64_t cx, std::int64_t cz) {
    const std::uint64_t index = (static_cast<std::uint64_t>(cx + (1 << 20)) << 21) ^
                                static_cast<std::uint64_t>(cz + (1 << 20));
    const double angle = 2.0 * kPi * rng.uniform4(index, 0)[0];
    return std::cos(angle) * (x - cx) + std::sin(angle) * (z - cz);
  };
  const auto fade = [](double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); };
  const double u = fade(x - fx), v = fade(z - fz);
  const double a = dotGradient(ix, iz) + u * (dotGradient(ix + 1, iz) - dotGradient(ix, iz));
  const double b =
      dotGradient(ix, iz + 1) + u * (dotGradient(ix + 1, iz + 1) - dotGradient(ix, iz + 1));
  return a + v * (b - a);
}

double smoothstep(double e0, double e1, double t) {
  const double s = std::clamp((t - e0) / (e1 - e0), 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}

// A generator's parameters at their defaults but for the seed.
template <class Params>
Params seededParams(std::uint64_t seed) {
  Params p;
  p.seed = seed;
  return p;
}

// The six holes of cavity and wells: hole k in cell (1 + k % 3, 1 + k / 3) of the 5 x 4 holed
// ground, its outline set by outline(k, hole).
template <class Outline>
std::vector<GroundHole> sixHoles(const Outline& outline) {
  std::vector<GroundHole> holes;
  for (int k = 0; k < 6; ++k) {
    GroundHole hole;
    hole.cell_x = 1 + k % 3;
    hole.cell_z = 1 + k / 3;
    outline(k, hole);
    holes.push_back(hole);
  }
  return holes;
}

}  // namespace

void addFlatGround(MeshBuilder& mesh, double inner) {
  const std::vector<double> axis = gradedAxis(inner, kGroundStep, kGroundExtent);
  addHeightfield(mesh, axis, axis, [](double, double) { return 0.0; });
}

const std::vector<std::string>& sceneTypeNames() {
  static const std::vector<std::string> names = {"cavity", "wedge",   "corner", "spheres",
                                                 "wells",  "clutter", "terrain"};
  return names;
}

Scene makeSceneType(const std::string& name, std::uint64_t seed) {
  if (name == "cavity") return makeCavityScene();
  if (name == "wedge") return makeWedgeScene();
  if (name == "corner") return makeCornerScene();
  if (name == "spheres") return makeSpheresScene();
  if (name == "wells") return makeWellsScene();
  if (name == "clutter") return makeClutterScene(seed);
  if (name == "terrain") return makeTerrainScene(seed);
  throw Error("unknown scene type '" + name +
              "' (expected cavity, wedge, corner, spheres, wells, clutter or terrain)");
}

Scene makeCavityScene(const CavityParams& p) {
  // Bowls of one sphere radius and six depths (classic: rim radii 0.66 … 1.0 … 0.44 m, A = 1 −
  // h/2R from 0.875 down to 0.05).
  const double kRadius = p.radius;
  const auto& depths = p.depths;
  const auto holes = sixHoles([&](int k, GroundHole& hole) {
    hole.half_x = std::sqrt(depths[k] * (2.0 * kRadius - depths[k]));
  });
  MeshBuilder mesh;
  // Cells 2.2 R wide: the deep bowls bulge to the sphere's full radius R below the ground.
  const auto rims = addHoledGround(mesh, 5, 4, 2.2 * kRadius, kCurveSegments, holes, kGroundExtent);
  for (int k = 0; k < 6; ++k) addBowl(mesh, rims[k], kRadius, depths[k], kCurveSegments);
  return mesh.finish("cavity", lookAt(kRadius * Eigen::Vector3d(0.0, 4.4, 2.9),
                                      kRadius * Eigen::Vector3d(0.0, -0.8, 0.1), kUp, kFov));
}

Scene makeWedgeScene(const WedgeParams& p) {
  // Profile in x (flat ground, then each groove's rim, bottom edge, rim), extruded along z.
  const double kDepth = p.depth;          // groove depth unless the half-width cap applies
  const double kMaxHalf = 1.5 * p.depth;  // cap on the half-width of the wide grooves
  const double kGap = 0.4 * p.depth;      // flat ground between grooves
  // Classic: the narrowest groove in the middle of the view, where the camera sees deepest.
  const auto& angles_deg = p.angles_deg;
  double width = 4.0 * kGap;
  double half[5];
  for (int k = 0; k < 5; ++k) {
    half[k] = std::min(kDepth * std::tan(0.5 * angles_deg[k] * kPi / 180.0), kMaxHalf);
    width += 2.0 * half[k];
  }
  const double start = -0.5 * width;
  std::vector<Eigen::Vector2d> profile;  // (x, y)
  const std::vector<double> graded = gradedAxis(1.0, kGroundStep, kGroundExtent);
  for (std::size_t i = 0; i < graded.size() / 2; ++i) profile.emplace_back(start + graded[i], 0.0);
  double x = start;
  for (int k = 0; k < 5; ++k) {
    const double depth = half[k] / std::tan(0.5 * angles_deg[k] * kPi / 180.0);
    profile.emplace_back(x, 0.0);
    profile.emplace_back(x + half[k], -depth);
    x += 2.0 * half[k];
    profile.emplace_back(x, 0.0);
    x += kGap;
  }
  const double end = x - kGap;
  for (std::size_t i = graded.size() / 2 + 1; i < graded.size(); ++i) {
    profile.emplace_back(end + graded[i], 0.0);
  }
  const std::vector<double> zs = gradedAxis(8.0, kGroundStep, kGroundExtent);
  MeshBuilder mesh;
  std::vector<std::uint32_t> previous;
  for (std::size_t j = 0; j < zs.size(); ++j) {
    std::vector<std::uint32_t> row;
    for (const auto& p : profile) row.push_back(mesh.vertex({p.x(), p.y(), zs[j]}));
    if (j > 0) {
      for (std::size_t i = 0; i + 1 < row.size(); ++i) {
        mesh.quad(previous[i], previous[i + 1], row[i + 1], row[i], kUp);
      }
    }
    previous = row;
  }
  return mesh.finish("wedge", lookAt(kDepth * Eigen::Vector3d(-0.42, 7.0, 3.6),
                                     kDepth * Eigen::Vector3d(-0.42, -0.6, 0.3), kUp, kFov));
}

Scene makeCornerScene(const CornerParams& p) {
  // Floor [0, size]², four walls (classic: 4 m, walls 2.5 m), no ceiling: every ray that leaves
  // over the walls rises for ever, so no ground outside is needed.
  const double kSize = p.size, kHeight = p.height;
  MeshBuilder mesh;
  std::uint32_t v[8];
  for (int k = 0; k < 8; ++k) {
    v[k] = mesh.vertex({(k & 1) ? kSize : 0.0, (k & 4) ? kHeight : 0.0, (k & 2) ? kSize : 0.0});
  }
  const Eigen::Vector3d centre(0.5 * kSize, 0.5 * kHeight, 0.5 * kSize);
  const auto inward = [&](std::uint32_t a, std::uint32_t c) -> Eigen::Vector3d {
    return centre - 0.5 * (mesh.position(a) + mesh.position(c));
  };
  mesh.quad(v[0], v[1], v[3], v[2], inward(v[0], v[3]));  // floor
  mesh.quad(v[0], v[1], v[5], v[4], inward(v[0], v[5]));  // z = 0
  mesh.quad(v[2], v[3], v[7], v[6], inward(v[2], v[7]));  // z = size
  mesh.quad(v[0], v[2], v[6], v[4], inward(v[0], v[6]));  // x = 0
  mesh.quad(v[1], v[3], v[7], v[5], inward(v[1], v[7]));  // x = size
  const double s = kSize / 4.0, h = kHeight / 2.5;
  return mesh.finish("corner",
                     lookAt({3.7 * s, 2.3 * h, 3.7 * s}, {0.4 * s, 0.1 * h, 0.4 * s}, kUp, kFov));
}

Scene makeSpheresScene(const SpheresParams& p) {
  MeshBuilder mesh;
  addFlatGround(mesh, 6.0);
  // Classic: gaps of 0.1 … 0.3 m between neighbours, so the crevices are in view too.
  for (const auto& s : p.spheres) {
    addSphere(mesh, {s.x, s.radius, s.z}, s.radius, kCurveSegments);
  }
  return mesh.finish("spheres", lookAt({0.0, 3.8, 5.0}, {0.0, 0.55, 0.0}, kUp, kFov));
}

Scene makeWellsScene(const WellsParams& p) {
  const auto& wells = p.wells;
  const auto holes = sixHoles([&](int k, GroundHole& hole) {
    hole.circle = wells[k].circle;
    hole.half_x = wells[k].half_x;
    hole.half_z = wells[k].half_z;
  });
  MeshBuilder mesh;
  const auto rims = addHoledGround(mesh, 5, 4, 2.0, kCurveSegments, holes, kGroundExtent);
  for (int k = 0; k < 6; ++k) addWell(mesh, rims[k], wells[k].depth);
  return mesh.finish("wells", lookAt({0.0, 4.6, 3.0}, {0.0, -0.6, 0.1}, kUp, kFov));
}

Scene makeClutterScene(std::uint64_t seed) {
  return makeClutterScene(seededParams<ClutterParams>(seed));
}

Scene makeClutterScene(const ClutterParams& p) {
  // Up to 26 objects (classic) in [−2.8, 2.8]², 70% boxes, 30% columns, footprints at least
  // 4 cm apart; attempt i draws from counter i of the clutter stream, so the layout is a pure
  // function of the parameters.
  const int kObjects = p.objects;
  constexpr int kAttempts = 4000;
  constexpr double kRegion = 2.8, kMinGap = 0.04;
  const CounterRng rng(p.seed, kClutterStream);
  MeshBuilder mesh;
  addFlatGround(mesh, 6.0);
  std::vector<Eigen::Vector3d> placed;  // x, footprint radius, z
  for (int attempt = 0; attempt < kAttempts && static_cast<int>(placed.size()) < kObjects;
       ++attempt) {
    const auto a = rng.uniform4(static_cast<std::uint64_t>(attempt), 0);
    const auto b = rng.uniform4(static_cast<std::uint64_t>(attempt), 1);
    const double x = kRegion * (2.0 * a[0] - 1.0), z = kRegion * (2.0 * a[1] - 1.0);
    const bool box = a[2] < static_cast<float>(p.box_fraction);
    const double hx = 0.15 + 0.65 * b[0], hz = 0.15 + 0.65 * b[1];
    const double radius = 0.08 + 0.22 * b[0];
    const double footprint = box ? std::hypot(hx, hz) : radius;
    bool clear = true;
    for (const auto& p : placed) {
      clear = clear && std::hypot(p.x() - x, p.z() - z) >= p.y() + footprint + kMinGap;
    }
    if (!clear) continue;
    placed.emplace_back(x, footprint, z);
    if (box) {
      addBox(mesh, {x, 0.0, z}, hx, hz, p.height_scale * (0.2 + 1.4 * b[2]), 0.5 * kPi * a[3]);
    } else {
      addCylinder(mesh, {x, 0.0, z}, radius, p.height_scale * (0.8 + 1.7 * b[2]),
                  kCurveSegments / 2);
    }
  }
  return mesh.finish("clutter", lookAt({0.0, 4.3, 4.9}, {0.0, 0.3, 0.0}, kUp, kFov));
}

Scene makeTerrainScene(std::uint64_t seed) {
  return makeTerrainScene(seededParams<TerrainParams>(seed));
}

Scene makeTerrainScene(const TerrainParams& p) {
  const std::uint64_t seed = p.seed;
  // h = window · (1.4 · ridged − 1.2 · valleys − 1.3): ridged = Σ wₒ (1 − |nₒ|)² (sharp crests),
  // valleys = Σ wₒ |mₒ| (V-shaped creases), 4 octaves from 0.3 cycles/m, weights 1/2ᵒ; the
  // window fades the relief to the flat ground between |x|, |z| = 6 and 8 m; the offset 1.3 m
  // (the median of the raw relief for seed 1) sinks the valleys below the surrounding ground.
  constexpr double kInner = 8.0, kFlatFrom = 6.0;
  constexpr double kStep = 1.0 / 16.0;  // grid step, m: 10 points per smallest wavelength
  const double kBaseFrequency = p.base_frequency;
  constexpr double kOffset = 1.3;
  constexpr int kOctaves = 4;
  std::vector<CounterRng> ridge_rng, valley_rng;
  for (int o = 0; o < kOctaves; ++o) {
    ridge_rng.emplace_back(seed, kTerrainStream + 2 * o);
    valley_rng.emplace_back(seed, kTerrainStream + 2 * o + 1);
  }
  const auto height = [&](double x, double z) {
    const double window = (1.0 - smoothstep(kFlatFrom, kInner, std::abs(x))) *
                          (1.0 - smoothstep(kFlatFrom, kInner, std::abs(z)));
    if (window == 0.0) return 0.0;
    double ridged = 0.0, valleys = 0.0, weight = 1.0, frequency = kBaseFrequency;
    for (int o = 0; o < kOctaves; ++o) {
      const double r = 1.0 - std::abs(gradientNoise(ridge_rng[o], frequency * x, frequency * z));
      ridged += weight * r * r;
      valleys += weight * std::abs(gradientNoise(valley_rng[o], frequency * x, frequency * z));
      weight *= 0.5;
      frequency *= 2.0;
    }
    return p.amplitude * window * (1.4 * ridged - 1.2 * valleys - kOffset);
  };
  std::vector<double> axis = gradedAxis(kInner, kStep, kGroundExtent);
  MeshBuilder mesh;
  addHeightfield(mesh, axis, axis, height);
  return mesh.finish("terrain", lookAt({0.0, 7.0, 8.5}, {0.0, -0.3, 0.0}, kUp, kFov));
}

}  // namespace gtbake
