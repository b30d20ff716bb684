// Small scenes with closed-form answers, for the tests (docs/scenes.md "Closed-form test
// scenes"); built with the conventions of src/scene/procedural_scenes.h.
#pragma once

#include "scene/procedural_scenes.h"

namespace gtbake {

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
