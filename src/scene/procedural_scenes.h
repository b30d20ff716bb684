// The procedural scenes: the seven classic scene types of docs/scenes.md (the closed-form test
// scenes are in tests/support/test_scenes.h). The corpus of twelve types in seeded variants is
// scene_corpus.h.
//
// Conventions: metres, +Y up, ground y = 0, every ground reaching kGroundExtent in x and z (see
// docs/scenes.md for why that removes the bias of a finite world), curved surfaces tessellated
// with kCurveSegments steps per turn. Every builder is deterministic: the same arguments give
// the same vertices, triangles and camera, bit for bit.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace gtbake {

// Half-width of every ground, m: a feature 3 m tall sees the horizon of a finite ground at most
// atan(3/10⁴) = 3·10⁻⁴ rad below the true one, which changes A by at most (2/π)·3·10⁻⁴ ≈ 2·10⁻⁴.
constexpr double kGroundExtent = 1.0e4;
// Segments per full turn of every curved surface: facet normals within 2π/128 = 2.8° of the
// true normal (half of that at facet centres), the sagitta R(1 − cos(π/128)) = 3·10⁻⁴ R.
constexpr int kCurveSegments = 128;
// Vertical field of view of every camera, rad (≈ 46°): a normal lens, little distortion.
constexpr double kFov = 0.8;
// Ground grid step near the features, m: small enough to keep the flat cells well shaped.
constexpr double kGroundStep = 0.5;

class MeshBuilder;
// The flat ground y = 0 out to ±kGroundExtent: kGroundStep cells within ±inner, graded beyond.
void addFlatGround(MeshBuilder& mesh, double inner);

// The seven classic scene types in their fixed order: cavity, wedge, corner, spheres, wells,
// clutter, terrain (data/scenes/ holds them, seed 1).
const std::vector<std::string>& sceneTypeNames();
// Builds one classic scene type by name with its classic parameters; `seed` is used by clutter
// and terrain only. Throws gtbake::Error for an unknown name.
Scene makeSceneType(const std::string& name, std::uint64_t seed);

// Parameters of the classic types; the defaults are the classic scenes (docs/scenes.md). The
// corpus (scene_corpus.h) draws other values per variant.
struct CavityParams {
  double radius = 1.0;                                             // sphere radius R of every bowl
  std::array<double, 6> depths = {0.25, 0.5, 1.0, 1.4, 1.7, 1.9};  // h ∈ (0, 2R)
};
struct WedgeParams {
  std::array<double, 5> angles_deg = {120.0, 60.0, 30.0, 90.0, 150.0};  // openings, (0°, 180°)
  double depth = 1.0;  // groove depth unless the half-width cap 1.5 depth applies
};
struct CornerParams {
  double size = 4.0;    // square floor side
  double height = 2.5;  // wall height
};
struct SphereSpec {
  double x = 0.0, z = 0.0, radius = 1.0;  // resting on the ground
};
struct SpheresParams {
  std::vector<SphereSpec> spheres = {
      {1.0, -0.9, 1.5}, {-1.6, -0.5, 1.0}, {-0.45, 1.05, 0.5}, {0.75, 1.0, 0.25}};
};
struct WellSpec {
  bool circle = true;
  double half_x = 0.5, half_z = 0.5, depth = 1.0;  // circle: half_x is the radius
};
struct WellsParams {
  std::array<WellSpec, 6> wells = {{{true, 0.6, 0.6, 0.3},
                                    {true, 0.6, 0.6, 1.2},
                                    {true, 0.3, 0.3, 1.2},
                                    {true, 0.8, 0.8, 2.4},
                                    {false, 0.9, 0.15, 0.6},
                                    {false, 0.3, 0.9, 1.5}}};
};
struct ClutterParams {
  std::uint64_t seed = 1;
  int objects = 26;           // placed objects (at most)
  double box_fraction = 0.7;  // the rest are columns
  double height_scale = 1.0;  // scales every object's height
};
struct TerrainParams {
  std::uint64_t seed = 1;
  double amplitude = 1.0;       // scales the relief (1: ±~2 m)
  double base_frequency = 0.3;  // cycles per metre of the first octave
};

Scene makeCavityScene(const CavityParams& p = {});    // spherical bowls in 2.2R cells
Scene makeWedgeScene(const WedgeParams& p = {});      // five infinite V-grooves
Scene makeCornerScene(const CornerParams& p = {});    // open-topped room: 2- and 3-plane corners
Scene makeSpheresScene(const SpheresParams& p = {});  // spheres resting on the ground
Scene makeWellsScene(const WellsParams& p = {});      // cylindrical wells and slots in a slab
Scene makeClutterScene(std::uint64_t seed);           // seeded boxes and columns on the ground
Scene makeClutterScene(const ClutterParams& p);
Scene makeTerrainScene(std::uint64_t seed);  // seeded ridged-noise heightfield, ±~2 m
Scene makeTerrainScene(const TerrainParams& p);

}  // namespace gtbake
