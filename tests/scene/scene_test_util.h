// Helpers for the scene tests: mesh topology and brute-force ray casts (scratch directories and
// byte reads are tests/support's TempDir and readBytes).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "scene/scene.h"
#include "support/temp_dir.h"

namespace gtbake::test {

struct EdgeCensus {
  std::size_t edges = 0;         // undirected edges
  std::size_t boundary = 0;      // used by one triangle
  std::size_t non_manifold = 0;  // used by three or more
  std::size_t inconsistent = 0;  // used twice in the same direction (orientation flips)
};
// Counts how the triangles share their edges; `is_rim(a, b)` is asked of every boundary edge
// and the ones it rejects are counted in `stray_boundary`.
EdgeCensus edgeCensus(const Scene& scene);
std::size_t strayBoundaryEdges(const Scene& scene,
                               bool (*is_rim)(const Eigen::Vector3f&, const Eigen::Vector3f&));

// Distance along the ray to the nearest triangle (two-sided Möller–Trumbore over all
// triangles), or nothing.
std::optional<double> castRay(const Scene& scene, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& direction);
// Direction of the camera ray through the centre of pixel (i, j) of a w × h image.
Eigen::Vector3d pixelRay(const PerspectiveCamera& camera, int i, int j, int w, int h);

bool scenesIdentical(const Scene& a, const Scene& b);

}  // namespace gtbake::test
