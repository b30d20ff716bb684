#include "closed_form_scenes.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "common/math_constants.h"
#include "scene/mesh_builder.h"
#include "scene/procedural_scenes.h"

namespace gtbake::test {

namespace {

constexpr double kFov = 0.8;  // vertical field of view of every test camera, rad

std::uint32_t addVertex(Scene& s, const Eigen::Vector3d& p) {
  s.positions.push_back(p.cast<float>());
  return static_cast<std::uint32_t>(s.positions.size() - 1);
}

void addQuad(Scene& s, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  s.triangles.push_back({a, b, c});
  s.triangles.push_back({a, c, d});
}

void addGroundSquare(Scene& s, double half) {
  const auto a = addVertex(s, {-half, 0, -half});
  const auto b = addVertex(s, {-half, 0, half});
  const auto c = addVertex(s, {half, 0, half});
  const auto d = addVertex(s, {half, 0, -half});
  addQuad(s, a, b, c, d);
}

}  // namespace

Scene parallelPlanes(double height) {
  MeshBuilder mesh;
  const std::vector<double> axis = gradedAxis(1.0, 1.0, kGroundExtent);
  addHeightfield(mesh, axis, axis, [](double, double) { return 0.0; });
  addHeightfield(mesh, axis, axis, [&](double, double) { return height; });
  return mesh.finish("parallel_planes", lookAt({0, 0.5 * height, 0}, {0, 0, -1}, {0, 1, 0}, kFov));
}

Scene openPlane(double half) {
  Scene s;
  s.name = "open_plane";
  addGroundSquare(s, half);
  s.camera = lookAt({0, 2, 2}, {0, 0, 0}, Eigen::Vector3d::UnitY(), kFov);
  return s;
}

std::vector<Eigen::Vector3d> bowlRim(double radius, double depth, int segments) {
  const double rim = std::sqrt(depth * (2.0 * radius - depth));
  std::vector<Eigen::Vector3d> p;
  for (int j = 0; j < segments; ++j) {
    const double phi = 2.0 * kPi * j / segments;
    p.emplace_back(rim * std::cos(phi), 0.0, rim * std::sin(phi));
  }
  return p;
}

Scene sphericalBowl(double radius, double depth, int rings, int segments) {
  Scene s;
  s.name = "bowl";
  const double cy = radius - depth;
  const double theta_max = std::acos(cy / radius);
  const auto bottom = addVertex(s, {0, cy - radius, 0});
  std::vector<std::uint32_t> previous(segments, bottom);
  const std::vector<Eigen::Vector3d> rim = bowlRim(radius, depth, segments);
  for (int i = 1; i <= rings; ++i) {
    const double theta = theta_max * i / rings;
    std::vector<std::uint32_t> ring(segments);
    for (int j = 0; j < segments; ++j) {
      const double phi = 2.0 * kPi * j / segments;
      // The rim ring reuses the exact rim points so the opening is one planar polygon.
      ring[j] = i == rings ? addVertex(s, rim[j])
                           : addVertex(s, {radius * std::sin(theta) * std::cos(phi),
                                           cy - radius * std::cos(theta),
                                           radius * std::sin(theta) * std::sin(phi)});
    }
    for (int j = 0; j < segments; ++j) {
      const int k = (j + 1) % segments;
      if (i == 1) {
        s.triangles.push_back({bottom, ring[k], ring[j]});
      } else {
        addQuad(s, previous[j], previous[k], ring[k], ring[j]);
      }
    }
    previous = ring;
  }
  s.camera =
      lookAt({0, 1.5 * radius, 0.5 * radius}, {0, cy - radius, 0}, Eigen::Vector3d::UnitY(), kFov);
  return s;
}

std::vector<Eigen::Vector3d> wellOpening(double radius, int segments) {
  std::vector<Eigen::Vector3d> p;
  for (int j = 0; j < segments; ++j) {
    const double phi = 2.0 * kPi * j / segments;
    p.emplace_back(radius * std::cos(phi), 0.0, radius * std::sin(phi));
  }
  return p;
}

Scene cylindricalWell(double radius, double depth, int segments) {
  Scene s;
  s.name = "well";
  const std::vector<Eigen::Vector3d> top = wellOpening(radius, segments);
  const auto centre = addVertex(s, {0, -depth, 0});
  std::vector<std::uint32_t> lo(segments);
  std::vector<std::uint32_t> hi(segments);
  for (int j = 0; j < segments; ++j) {
    lo[j] = addVertex(s, top[j] - Eigen::Vector3d(0, depth, 0));
    hi[j] = addVertex(s, top[j]);
  }
  for (int j = 0; j < segments; ++j) {
    const int k = (j + 1) % segments;
    s.triangles.push_back({centre, lo[k], lo[j]});
    addQuad(s, lo[j], lo[k], hi[k], hi[j]);
  }
  s.camera = lookAt({0, 2 * depth, 0.01}, {0, -depth, 0}, Eigen::Vector3d::UnitY(), kFov);
  return s;
}

double polygonFormFactor(const Eigen::Vector3d& x, const Eigen::Vector3d& n,
                         const std::vector<Eigen::Vector3d>& p) {
  double sum = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector3d a = (p[i] - x).normalized();
    const Eigen::Vector3d b = (p[(i + 1) % p.size()] - x).normalized();
    const Eigen::Vector3d c = a.cross(b);
    const double angle = std::atan2(c.norm(), a.dot(b));
    sum += angle * n.dot(c.normalized());
  }
  return std::fabs(sum) / (2.0 * kPi);
}

double inradius(const Scene& scene, const Eigen::Vector3d& centre) {
  double r = INFINITY;
  for (const auto& t : scene.triangles) {
    const Eigen::Vector3d a = scene.positions[t[0]].cast<double>();
    const Eigen::Vector3d b = scene.positions[t[1]].cast<double>();
    const Eigen::Vector3d c = scene.positions[t[2]].cast<double>();
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    r = std::min(r, std::fabs(n.dot(centre - a)));
  }
  return r;
}

}  // namespace gtbake::test
