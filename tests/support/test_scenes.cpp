#include "support/test_scenes.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/math_constants.h"
#include "scene/holed_ground.h"
#include "scene/mesh_builder.h"

namespace gtbake {
namespace {

const Eigen::Vector3d kUp = Eigen::Vector3d::UnitY();
const Eigen::Vector3d kNorth = -Eigen::Vector3d::UnitZ();  // image "up" of top-down cameras

void requirePositive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw Error(std::string(what) + " must be a positive finite number");
  }
}

void requireSegments(int segments) {
  if (segments < 8 || segments % 8 != 0) {
    throw Error("the tessellation must be a multiple of 8 segments, at least 8, not " +
                std::to_string(segments));
  }
}

}  // namespace

Scene makeSphericalCavityScene(double R, double h, int segments) {
  requirePositive(R, "the cavity's sphere radius");
  requireSegments(segments);
  if (!(h > 0.0 && h < 2.0 * R)) throw Error("the cavity depth must lie in (0, 2R)");
  GroundHole hole;
  hole.half_x = std::sqrt(h * (2.0 * R - h));
  MeshBuilder mesh;
  const double cell = 2.5 * R;  // wider than the bowl's widest circle (radius ≤ R)
  const auto rims = addHoledGround(mesh, 1, 1, cell, segments, {hole}, kGroundExtent);
  addBowl(mesh, rims[0], R, h, segments);
  return mesh.finish("spherical_cavity", lookAt({0.0, 4.0 * R, 0.0}, {0.0, 0.0, 0.0}, kNorth, 0.5));
}

Scene makeCylinderWellScene(double radius, double depth, int segments) {
  requirePositive(radius, "the well radius");
  requirePositive(depth, "the well depth");
  requireSegments(segments);
  GroundHole hole;
  hole.half_x = radius;
  MeshBuilder mesh;
  const auto rims = addHoledGround(mesh, 1, 1, 3.0 * radius, segments, {hole}, kGroundExtent);
  addWell(mesh, rims[0], depth);
  return mesh.finish("cylinder_well",
                     lookAt({0.0, 4.0 * radius, 0.0}, {0.0, -depth, 0.0}, kNorth, 0.5));
}

Scene makeSphereOnPlaneScene(double R, int segments) {
  requirePositive(R, "the sphere radius");
  requireSegments(segments);
  MeshBuilder mesh;
  const double step = 0.25 * R;
  const auto axis = gradedAxis(8.0 * step * 2.0, step, kGroundExtent);
  addHeightfield(mesh, axis, axis, [](double, double) { return 0.0; });
  addSphere(mesh, {0.0, R, 0.0}, R, segments);
  return mesh.finish("sphere_on_plane",
                     lookAt({0.0, 2.5 * R, 3.5 * R}, {0.0, 0.5 * R, 0.0}, kUp, 0.8));
}

Scene makeVGrooveScene(double opening, double depth) {
  requirePositive(depth, "the groove depth");
  if (!(opening > 0.0 && opening < kPi)) throw Error("the groove opening angle must lie in (0, π)");
  const double half = depth * std::tan(0.5 * opening);
  std::vector<double> xs = gradedAxis(0.0, half, kGroundExtent);
  std::vector<double> ys(xs.size(), 0.0);
  // gradedAxis(0, half, …) is {…, −2·half, 0, 2·half, …}: replace 0 by the groove.
  const auto mid = static_cast<std::ptrdiff_t>(xs.size() / 2);
  xs[mid] = 0.0;
  ys[mid] = -depth;
  xs.insert(xs.begin() + mid + 1, half);
  ys.insert(ys.begin() + mid + 1, 0.0);
  xs.insert(xs.begin() + mid, -half);
  ys.insert(ys.begin() + mid, 0.0);
  const auto zs = gradedAxis(4.0 * half, half, kGroundExtent);
  MeshBuilder mesh;
  std::vector<std::uint32_t> previous;
  for (std::size_t j = 0; j < zs.size(); ++j) {
    std::vector<std::uint32_t> row;
    for (std::size_t i = 0; i < xs.size(); ++i) row.push_back(mesh.vertex({xs[i], ys[i], zs[j]}));
    if (j > 0) {
      for (std::size_t i = 0; i + 1 < row.size(); ++i) {
        mesh.quad(previous[i], previous[i + 1], row[i + 1], row[i], kUp);
      }
    }
    previous = row;
  }
  const double height = 2.0 * std::max(half, depth);
  return mesh.finish("v_groove", lookAt({0.0, height, 0.0}, {0.0, -depth, 0.0}, kNorth, 0.5));
}

Scene makeOpenPlaneScene() {
  MeshBuilder mesh;
  const auto axis = gradedAxis(4.0, 0.5, kGroundExtent);
  addHeightfield(mesh, axis, axis, [](double, double) { return 0.0; });
  return mesh.finish("open_plane", lookAt({0.0, 2.0, 2.0}, {0.0, 0.0, 0.0}, kUp, 0.8));
}

Scene makeClosedBoxScene() {
  MeshBuilder mesh;
  addBox(mesh, {0.0, 0.0, 0.0}, 1.0, 1.0, 2.0, 0.0);
  return mesh.finish("closed_box", lookAt({0.0, 1.0, 0.0}, {0.0, 1.0, -1.0}, kUp, 0.8));
}

}  // namespace gtbake
