#include "scene_test_util.h"

#include <Eigen/Geometry>
#include <cmath>
#include <map>

namespace gtbake::test {

namespace {
using Edge = std::pair<std::uint32_t, std::uint32_t>;
// For every undirected edge (low, high): how many times it is used low→high and high→low.
std::map<Edge, std::pair<int, int>> edgeUses(const Scene& scene) {
  std::map<Edge, std::pair<int, int>> uses;
  for (const auto& t : scene.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      auto& use = uses[{std::min(a, b), std::max(a, b)}];
      (a < b ? use.first : use.second) += 1;
    }
  }
  return uses;
}
}  // namespace

EdgeCensus edgeCensus(const Scene& scene) {
  EdgeCensus census;
  for (const auto& [edge, use] : edgeUses(scene)) {
    const int total = use.first + use.second;
    ++census.edges;
    if (total == 1) ++census.boundary;
    if (total > 2) ++census.non_manifold;
    if (total == 2 && use.first != 1) ++census.inconsistent;
  }
  return census;
}

std::size_t strayBoundaryEdges(const Scene& scene,
                               bool (*is_rim)(const Eigen::Vector3f&, const Eigen::Vector3f&)) {
  std::size_t stray = 0;
  for (const auto& [edge, use] : edgeUses(scene)) {
    if (use.first + use.second == 1 &&
        !is_rim(scene.positions[edge.first], scene.positions[edge.second])) {
      ++stray;
    }
  }
  return stray;
}

std::optional<double> castRay(const Scene& scene, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& direction) {
  std::optional<double> nearest;
  for (const auto& t : scene.triangles) {
    const Eigen::Vector3d v0 = scene.positions[t[0]].cast<double>();
    const Eigen::Vector3d e1 = scene.positions[t[1]].cast<double>() - v0;
    const Eigen::Vector3d e2 = scene.positions[t[2]].cast<double>() - v0;
    const Eigen::Vector3d p = direction.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-300) continue;
    const Eigen::Vector3d s = origin - v0;
    const double u = s.dot(p) / det;
    if (u < 0.0 || u > 1.0) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = direction.dot(q) / det;
    if (v < 0.0 || u + v > 1.0) continue;
    const double dist = e2.dot(q) / det;
    if (dist > 1e-9 && (!nearest || dist < *nearest)) nearest = dist;
  }
  return nearest;
}

Eigen::Vector3d pixelRay(const PerspectiveCamera& camera, int i, int j, int w, int h) {
  const double tan_half = std::tan(0.5 * camera.yfov);
  const double aspect = static_cast<double>(w) / h;
  const double x = (2.0 * (i + 0.5) / w - 1.0) * tan_half * aspect;
  const double y = (1.0 - 2.0 * (j + 0.5) / h) * tan_half;
  return (x * camera.basis.col(0) + y * camera.basis.col(1) - camera.basis.col(2)).normalized();
}

bool scenesIdentical(const Scene& a, const Scene& b) {
  return a.name == b.name && a.positions == b.positions && a.triangles == b.triangles &&
         a.camera.position == b.camera.position && a.camera.basis == b.camera.basis &&
         a.camera.yfov == b.camera.yfov;
}

}  // namespace gtbake::test
