// The procedural scenes: the seven scene types of docs/scenes.md "The seven scene types" and small
// closed-form test scenes.
//
// Conventions: metres, +Y up, ground y = 0, every ground reaching kGroundExtent in x and z (see
// docs/scenes.md for why that removes the bias of a finite world), curved surfaces tessellated
// with kCurveSegments steps per turn. Every builder is deterministic: the same arguments give
// the same vertices, triangles and camera, bit for bit.
#pragma once

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

// The seven scene types in their fixed order: cavity, wedge, corner, spheres, wells, clutter,
// terrain.
const std::vector<std::string>& sceneTypeNames();
// Builds one scene type by name; `seed` is used by clutter and terrain only. Throws
// gtbake::Error for an unknown name.
Scene makeSceneType(const std::string& name, std::uint64_t seed);

Scene makeCavityScene();   // six spherical bowls, R = 1 m, depths 0.25 … 1.9 m
Scene makeWedgeScene();    // five infinite V-grooves, opening angles 30°, 60°, 90°, 120°, 150°
Scene makeCornerScene();   // open-topped 4 × 4 m room, walls 2.5 m: 2- and 3-plane corners
Scene makeSpheresScene();  // spheres of radii 0.25, 0.5, 1.0, 1.5 m resting on the ground
Scene makeWellsScene();    // cylindrical wells and rectangular slots with floors, in a slab
Scene makeClutterScene(std::uint64_t seed);  // seeded boxes and columns on the ground
Scene makeTerrainScene(std::uint64_t seed);  // seeded ridged-noise heightfield, ±~2 m

// Closed-form test scenes (each camera looks at its feature; the centre pixel sees the named
// point where one is named).
//
// One spherical bowl (sphere radius R, depth h ∈ (0, 2R)) in an infinite ground; the camera
// looks straight down its axis (centre pixel: the bottom of the bowl). Closed form: every point
// of the bowl has A = (2R − h)/(2R) (the view factor from a point inside a sphere to a part of it
// is that part's area over 4πR²).
Scene makeSphericalCavityScene(double R, double h, int segments = kCurveSegments);
// One cylindrical well (radius, depth) with a flat floor; camera straight down its axis (centre
// pixel: the centre of the floor).
Scene makeCylinderWellScene(double radius, double depth, int segments = kCurveSegments);
// One sphere of radius R resting on the ground at the origin; camera from above and the side.
Scene makeSphereOnPlaneScene(double R, int segments = kCurveSegments);
// One infinite V-groove along z, opening angle `opening` (radians) and depth `depth`; camera
// straight down (centre pixel: the bottom edge of the groove).
Scene makeVGrooveScene(double opening, double depth);
// Nothing but the ground (A = G = 1 everywhere); camera looking down at 45°.
Scene makeOpenPlaneScene();
// A closed 2 m cube seen from its centre (A = 0 and G = 0 everywhere: no path escapes).
Scene makeClosedBoxScene();

}  // namespace gtbake
