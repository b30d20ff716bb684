// MeshBuilder: welded, consistently oriented triangle meshes for the procedural scenes.
//
// Vertices are welded by their exact single-precision position: two surfaces that meet share the
// vertices of their common edge as long as both compute the same double and round it to the same
// float, which the builders guarantee by computing every shared point in one place. Welding is
// what makes the meshes watertight (no T-junctions, no cracks light could leak through).
//
// Orientation: every triangle is given with a `front` direction and is stored counter-clockwise
// seen from that side, so its geometric normal (b − a) × (c − a) points to the front. The sweep
// treats surfaces as two-sided; orientation only keeps the meshes tidy and the edge tests simple.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace gtbake {

class MeshBuilder {
 public:
  // Index of the vertex at `p` (rounded to float); equal float positions give the same index.
  std::uint32_t vertex(const Eigen::Vector3d& p);
  Eigen::Vector3d position(std::uint32_t index) const;

  // Adds (a, b, c) wound so that its normal faces `front`; skips triangles that welding collapsed.
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, const Eigen::Vector3d& front);
  // Adds the quad a-b-c-d (in order around its boundary) as the triangles (a, b, c), (a, c, d).
  void quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d,
            const Eigen::Vector3d& front);

  Scene finish(std::string name, const PerspectiveCamera& camera) const;

 private:
  std::map<std::array<float, 3>, std::uint32_t> index_;
  std::vector<Eigen::Vector3f> positions_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
};

// Camera at `eye` looking at `target`; `up` picks the roll (it must not be parallel to the view).
PerspectiveCamera lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                         const Eigen::Vector3d& up, double yfov);

// Sorted coordinates from −extent to +extent: uniform steps of `step` on [−inner, inner] (inner a
// multiple of step), then steps that double outward, the last one ending exactly at ±extent. The
// geometric grading keeps every ground triangle within a small factor of its distance from the
// features, so a ground many kilometres wide costs a few hundred triangles and no precision.
std::vector<double> gradedAxis(double inner, double step, double extent);

// Heightfield y = height(x, z) on the grid xs × zs (a closed-form plane when height is 0), facing
// +Y.
template <typename HeightFn>
void addHeightfield(MeshBuilder& mesh, const std::vector<double>& xs, const std::vector<double>& zs,
                    HeightFn height) {
  std::vector<std::uint32_t> previous;
  std::vector<std::uint32_t> row(xs.size());
  for (std::size_t j = 0; j < zs.size(); ++j) {
    for (std::size_t i = 0; i < xs.size(); ++i) {
      row[i] = mesh.vertex(Eigen::Vector3d(xs[i], height(xs[i], zs[j]), zs[j]));
    }
    if (j > 0) {
      for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
        mesh.quad(previous[i], previous[i + 1], row[i + 1], row[i], Eigen::Vector3d::UnitY());
      }
    }
    previous = row;
  }
}

// Closed UV sphere: `segments` steps in longitude (a multiple of 2), segments/2 in latitude, one
// vertex at each pole (the south pole is the lowest point, so a sphere resting on y = 0 touches
// it with exactly that vertex). Outward facing.
void addSphere(MeshBuilder& mesh, const Eigen::Vector3d& centre, double radius, int segments);

// Closed upright cylinder on y = base.y() with flat caps, `segments` sides. Outward facing.
void addCylinder(MeshBuilder& mesh, const Eigen::Vector3d& base, double radius, double height,
                 int segments);

// Closed box standing on y = base.y(), half-extents (hx, hz) in its own frame rotated by `yaw`
// radians about +Y, height `height`. Outward facing.
void addBox(MeshBuilder& mesh, const Eigen::Vector3d& base, double hx, double hz, double height,
            double yaw);
// Box centred at `centre` with half-extents h along the orthonormal axes a0, a1, a2.
void addOrientedBox(MeshBuilder& mesh, const Eigen::Vector3d& centre, const Eigen::Vector3d& a0,
                    const Eigen::Vector3d& a1, const Eigen::Vector3d& a2, const Eigen::Vector3d& h);

}  // namespace gtbake
