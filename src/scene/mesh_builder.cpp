#include "scene/mesh_builder.h"

#include <Eigen/Geometry>
#include <cmath>

#include "common/math_constants.h"

namespace gtbake {

std::uint32_t MeshBuilder::vertex(const Eigen::Vector3d& p) {
  const std::array<float, 3> key = {static_cast<float>(p.x()), static_cast<float>(p.y()),
                                    static_cast<float>(p.z())};
  const auto found = index_.find(key);
  if (found != index_.end()) return found->second;
  const auto index = static_cast<std::uint32_t>(positions_.size());
  index_.emplace(key, index);
  positions_.emplace_back(key[0], key[1], key[2]);
  return index;
}

Eigen::Vector3d MeshBuilder::position(std::uint32_t index) const {
  return positions_[index].cast<double>();
}

void MeshBuilder::triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c,
                           const Eigen::Vector3d& front) {
  if (a == b || b == c || c == a) return;
  const Eigen::Vector3d pa = position(a);
  const Eigen::Vector3d normal = (position(b) - pa).cross(position(c) - pa);
  if (normal.dot(front) < 0.0) std::swap(b, c);
  triangles_.push_back({a, b, c});
}

void MeshBuilder::quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d,
                       const Eigen::Vector3d& front) {
  triangle(a, b, c, front);
  triangle(a, c, d, front);
}

Scene MeshBuilder::finish(std::string name, const PerspectiveCamera& camera) const {
  Scene scene;
  scene.name = std::move(name);
  scene.type = scene.name;
  scene.positions = positions_;
  scene.triangles = triangles_;
  scene.camera = camera;
  return scene;
}

PerspectiveCamera lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                         const Eigen::Vector3d& up, double yfov) {
  const Eigen::Vector3d backward = (eye - target).normalized();
  const Eigen::Vector3d right = up.cross(backward).normalized();
  const Eigen::Vector3d true_up = backward.cross(right);
  PerspectiveCamera camera;
  camera.position = eye;
  camera.basis.col(0) = right;
  camera.basis.col(1) = true_up;
  camera.basis.col(2) = backward;
  camera.yfov = yfov;
  return camera;
}

std::vector<double> gradedAxis(double inner, double step, double extent) {
  const int cells = static_cast<int>(std::lround(inner / step));
  std::vector<double> positive;
  for (int i = 0; i <= cells; ++i) positive.push_back(i * step);
  double width = 2.0 * step;
  // Each step doubles; the last one takes what is left (between one and two times its width).
  while (extent - positive.back() >= 2.0 * width) {
    positive.push_back(positive.back() + width);
    width *= 2.0;
  }
  positive.push_back(extent);
  std::vector<double> axis;
  for (std::size_t i = positive.size(); i-- > 1;) axis.push_back(-positive[i]);
  axis.insert(axis.end(), positive.begin(), positive.end());
  return axis;
}

void addSphere(MeshBuilder& mesh, const Eigen::Vector3d& centre, double radius, int segments) {
  const int rings = segments / 2;
  const std::uint32_t south = mesh.vertex(centre - radius * Eigen::Vector3d::UnitY());
  const std::uint32_t north = mesh.vertex(centre + radius * Eigen::Vector3d::UnitY());
  std::vector<std::vector<std::uint32_t>> ring(rings - 1);
  for (int r = 1; r < rings; ++r) {
    const double polar = kPi * r / rings;  // from the south pole
    for (int s = 0; s < segments; ++s) {
      const double azimuth = 2.0 * kPi * s / segments;
      const Eigen::Vector3d d(std::sin(polar) * std::cos(azimuth), -std::cos(polar),
                              std::sin(polar) * std::sin(azimuth));
      ring[r - 1].push_back(mesh.vertex(centre + radius * d));
    }
  }
  for (int s = 0; s < segments; ++s) {
    const int t = (s + 1) % segments;
    const auto outward = [&](std::uint32_t v) -> Eigen::Vector3d {
      return mesh.position(v) - centre;
    };
    mesh.triangle(south, ring[0][s], ring[0][t], outward(ring[0][s]));
    for (int r = 0; r + 1 < rings - 1; ++r) {
      mesh.quad(ring[r][s], ring[r][t], ring[r + 1][t], ring[r + 1][s], outward(ring[r][s]));
    }
    mesh.triangle(north, ring[rings - 2][s], ring[rings - 2][t], outward(ring[rings - 2][s]));
  }
}

void addCylinder(MeshBuilder& mesh, const Eigen::Vector3d& base, double radius, double height,
                 int segments) {
  const Eigen::Vector3d top_centre = base + height * Eigen::Vector3d::UnitY();
  const std::uint32_t bottom = mesh.vertex(base);
  const std::uint32_t top = mesh.vertex(top_centre);
  std::vector<std::uint32_t> low;
  std::vector<std::uint32_t> high;
  for (int s = 0; s < segments; ++s) {
    const double azimuth = 2.0 * kPi * s / segments;
    const Eigen::Vector3d d(radius * std::cos(azimuth), 0.0, radius * std::sin(azimuth));
    low.push_back(mesh.vertex(base + d));
    high.push_back(mesh.vertex(top_centre + d));
  }
  for (int s = 0; s < segments; ++s) {
    const int t = (s + 1) % segments;
    Eigen::Vector3d outward = mesh.position(low[s]) + mesh.position(low[t]) - 2.0 * base;
    outward.y() = 0.0;
    mesh.quad(low[s], low[t], high[t], high[s], outward);
    mesh.triangle(bottom, low[s], low[t], -Eigen::Vector3d::UnitY());
    mesh.triangle(top, high[s], high[t], Eigen::Vector3d::UnitY());
  }
}

namespace {

// The six faces of a box whose corner k sits on the + side of axis a_i where bit i of k is set.
void addBoxFaces(MeshBuilder& mesh, const std::array<std::uint32_t, 8>& v,
                 const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& a2) {
  mesh.quad(v[0], v[1], v[3], v[2], -a2);
  mesh.quad(v[4], v[5], v[7], v[6], a2);
  mesh.quad(v[0], v[1], v[5], v[4], -a1);
  mesh.quad(v[2], v[3], v[7], v[6], a1);
  mesh.quad(v[0], v[2], v[6], v[4], -a0);
  mesh.quad(v[1], v[3], v[7], v[5], a0);
}

}  // namespace

void addBox(MeshBuilder& mesh, const Eigen::Vector3d& base, double hx, double hz, double height,
            double yaw) {
  const Eigen::Vector3d ax(std::cos(yaw), 0.0, -std::sin(yaw));
  const Eigen::Vector3d az(std::sin(yaw), 0.0, std::cos(yaw));
  std::array<std::uint32_t, 8> v{};
  for (int k = 0; k < 8; ++k) {
    const double sx = (k & 1) ? 1.0 : -1.0;
    const double sz = (k & 2) ? 1.0 : -1.0;
    const double y = (k & 4) ? height : 0.0;
    v[k] = mesh.vertex(base + sx * hx * ax + sz * hz * az + y * Eigen::Vector3d::UnitY());
  }
  addBoxFaces(mesh, v, ax, az, Eigen::Vector3d::UnitY());
}

void addOrientedBox(MeshBuilder& mesh, const Eigen::Vector3d& centre, const Eigen::Vector3d& a0,
                    const Eigen::Vector3d& a1, const Eigen::Vector3d& a2,
                    const Eigen::Vector3d& h) {
  std::array<std::uint32_t, 8> v{};
  for (int k = 0; k < 8; ++k) {
    v[k] = mesh.vertex(centre + ((k & 1) ? 1.0 : -1.0) * h[0] * a0 +
                       ((k & 2) ? 1.0 : -1.0) * h[1] * a1 + ((k & 4) ? 1.0 : -1.0) * h[2] * a2);
  }
  addBoxFaces(mesh, v, a0, a1, a2);
}

}  // namespace gtbake
