// Scenes whose A (and, for the bowl, every p_k) has a closed form, built directly as Scene objects,
// and the exact form factor of a polygon, used to measure what tessellation does to the closed
// forms (docs/sweep.md, "Tests"). These are the shapes src/scene does not build: a finite plane
// whose edge is in view, and a bowl and a well with no ground around their opening (so the sky is
// seen exactly through one planar polygon). The closed box and the sphere on a plane are
// tests/support's (makeClosedBoxScene, makeSphereOnPlaneScene in tests/support/test_scenes.h).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "scene/scene.h"

namespace gtbake::test {

// Square of half-size `half` in y = 0, camera above it looking down at 45°.
Scene openPlane(double half);

// Two infinite parallel planes: the floor y = 0 and the ceiling y = height, both out to
// ±kGroundExtent (graded cells, so the ray offsets stay those of a small scene near the origin).
Scene parallelPlanes(double height);

// Spherical bowl: the part y ≤ 0 of the sphere of radius R centred at (0, R − h, 0), depth h,
// `rings` latitude steps from the bottom vertex to the rim ring at y = 0, `segments` longitudes.
// Every vertex lies on the sphere and the rim ring is planar, so the mesh is convex and a point
// inside sees the sky exactly through the rim polygon.
Scene sphericalBowl(double radius, double depth, int rings, int segments);
std::vector<Eigen::Vector3d> bowlRim(double radius, double depth, int segments);

// Cylindrical well: floor disk at y = −depth, walls up to y = 0, a regular `segments`-gon of
// circumradius `radius`.
Scene cylindricalWell(double radius, double depth, int segments);
std::vector<Eigen::Vector3d> wellOpening(double radius, int segments);

// Exact (1/π)∫ cos dω over the directions from x through the planar polygon `p` (Lambert's
// formula), for a polygon wholly above x's tangent plane: the A of x when only `p` shows sky.
double polygonFormFactor(const Eigen::Vector3d& x, const Eigen::Vector3d& n,
                         const std::vector<Eigen::Vector3d>& p);

// Smallest distance from `centre` to the plane of any triangle of `scene`.
double inradius(const Scene& scene, const Eigen::Vector3d& centre);

}  // namespace gtbake::test
