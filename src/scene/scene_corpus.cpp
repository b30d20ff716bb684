// The corpus: the classic types' variant parameters and the building blocks of the new types
// (scene_corpus.h; the ranges are listed in docs/scenes.md).
#include "scene/scene_corpus.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/math_constants.h"
#include "common/rng.h"
#include "scene/procedural_scenes.h"

namespace gtbake {
namespace {

// Random stream of the variant parameters of classic type t: kVariantStream + t.
constexpr std::uint64_t kVariantStream = 0x76617269;  // "vari"

Scene classicVariant(std::size_t type, const std::string& name, int variant, std::uint64_t seed) {
  const VariantDraws d(seed, kVariantStream + type, variant);
  if (name == "cavity") {
    CavityParams p;
    p.radius = d.in(0, 0.6, 1.4);
    // Depths spread over (0, 2R): one in each sixth of the range, so every variant spans A.
    for (int k = 0; k < 6; ++k) p.depths[k] = p.radius * (0.1 + (k + d(1 + k)) * 1.85 / 6.0);
    return makeCavityScene(p);
  }
  if (name == "wedge") {
    WedgeParams p;
    for (int k = 0; k < 5; ++k) p.angles_deg[k] = 20.0 + (k + d(k)) * 140.0 / 5.0;
    std::swap(p.angles_deg[0], p.angles_deg[2]);  // the narrowest groove near the middle
    p.depth = d.in(5, 0.5, 1.5);
    return makeWedgeScene(p);
  }
  if (name == "corner") {
    // Walls at least as tall, relative to the floor, as the classic 2.5 / 4: the camera, scaled
    // with both, then sees no sky over them.
    const double size = d.in(0, 2.5, 6.0);
    return makeCornerScene({size, size * d.in(1, 0.625, 0.9)});
  }
  if (name == "spheres") {
    // Spheres on a ring around the origin, radii 0.2–1.5 m, gaps 0.05–0.5 m between neighbours.
    SpheresParams p;
    p.spheres.clear();
    const int count = 3 + static_cast<int>(4.0 * d(0));
    double angle = 2.0 * kPi * d(1);
    for (int k = 0; k < count; ++k) {
      const double r = d.in(2 + k, 0.2, 1.2);
      const double distance = 0.8 + 1.6 * d(10 + k);
      const SphereSpec s{distance * std::cos(angle), distance * std::sin(angle), r};
      bool clear = true;
      for (const SphereSpec& o : p.spheres) {
        clear = clear && std::hypot(o.x - s.x, o.z - s.z) > 2.0 * std::sqrt(o.radius * s.radius);
      }
      if (clear) p.spheres.push_back(s);
      angle += 2.0 * kPi / count;
    }
    return makeSpheresScene(p);
  }
  if (name == "wells") {
    WellsParams p;
    for (int k = 0; k < 6; ++k) {
      WellSpec& w = p.wells[k];
      w.circle = d(4 * k) < 0.6;
      w.half_x = d.in(4 * k + 1, 0.12, 0.85);
      w.half_z = w.circle ? w.half_x : d.in(4 * k + 2, 0.12, 0.85);
      w.depth = std::max(w.half_x, w.half_z) * d.in(4 * k + 3, 0.3, 5.0);  // aspect 0.15 … 2.5
    }
    return makeWellsScene(p);
  }
  if (name == "clutter") {
    ClutterParams p;
    p.seed = seed * 16 + static_cast<std::uint64_t>(variant);
    p.objects = 8 + static_cast<int>(34.0 * d(0));  // sparse to dense
    p.box_fraction = d.in(1, 0.3, 0.9);
    p.height_scale = d.in(2, 0.5, 1.6);
    return makeClutterScene(p);
  }
  TerrainParams p;
  p.seed = seed * 16 + static_cast<std::uint64_t>(variant);
  p.amplitude = d.in(0, 0.4, 1.4);  // gentle to rough
  p.base_frequency = d.in(1, 0.2, 0.45);
  return makeTerrainScene(p);
}

}  // namespace

const std::vector<std::string>& corpusTypeNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all = sceneTypeNames();
    for (const char* extra : {"interior", "colonnade", "rocks", "thin", "mechanical"}) {
      all.emplace_back(extra);
    }
    return all;
  }();
  return names;
}

Scene makeCorpusScene(const std::string& type, int variant, std::uint64_t seed) {
  if (variant < 0) throw Error("a scene variant must be 0 or more");
  const auto& names = corpusTypeNames();
  const auto found = std::find(names.begin(), names.end(), type);
  if (found == names.end()) throw Error("unknown scene type '" + type + "'");
  const auto index = static_cast<std::size_t>(found - names.begin());
  Scene scene;
  if (index < sceneTypeNames().size()) {
    scene = variant == 0 ? makeSceneType(type, seed) : classicVariant(index, type, variant, seed);
  } else if (type == "interior") {
    scene = makeInteriorScene(seed, variant);
  } else if (type == "colonnade") {
    scene = makeColonnadeScene(seed, variant);
  } else if (type == "rocks") {
    scene = makeRocksScene(seed, variant);
  } else if (type == "thin") {
    scene = makeThinScene(seed, variant);
  } else {
    scene = makeMechanicalScene(seed, variant);
  }
  scene.name = type + "_" + std::to_string(variant);
  scene.type = type;
  return scene;
}

void addExtrusion(MeshBuilder& mesh, const Eigen::Vector3d& base,
                  const std::vector<Eigen::Vector2d>& profile, double height) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  const std::uint32_t bottom = mesh.vertex(base);
  const std::uint32_t top = mesh.vertex(base + height * up);
  std::vector<std::uint32_t> low, high;
  for (const Eigen::Vector2d& p : profile) {
    low.push_back(mesh.vertex(base + Eigen::Vector3d(p.x(), 0.0, p.y())));
    high.push_back(mesh.vertex(base + Eigen::Vector3d(p.x(), height, p.y())));
  }
  const std::size_t n = profile.size();
  for (std::size_t s = 0; s < n; ++s) {
    const std::size_t t = (s + 1) % n;
    const Eigen::Vector2d middle = profile[s] + profile[t];  // outward: the profile is star-shaped
    const Eigen::Vector3d outward(middle.x(), 0.0, middle.y());
    mesh.quad(low[s], low[t], high[t], high[s], outward);
    mesh.triangle(bottom, low[s], low[t], -up);
    mesh.triangle(top, high[s], high[t], up);
  }
}

void addTube(MeshBuilder& mesh, const Eigen::Vector3d& base, double inner, double outer,
             double height, int segments) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  std::vector<std::uint32_t> ring[4];  // inner low, outer low, inner high, outer high
  for (int s = 0; s < segments; ++s) {
    const double azimuth = 2.0 * kPi * s / segments;
    const Eigen::Vector3d d(std::cos(azimuth), 0.0, std::sin(azimuth));
    ring[0].push_back(mesh.vertex(base + inner * d));
    ring[1].push_back(mesh.vertex(base + outer * d));
    ring[2].push_back(mesh.vertex(base + inner * d + height * up));
    ring[3].push_back(mesh.vertex(base + outer * d + height * up));
  }
  for (int s = 0; s < segments; ++s) {
    const int t = (s + 1) % segments;
    Eigen::Vector3d out = mesh.position(ring[1][s]) + mesh.position(ring[1][t]) - 2.0 * base;
    out.y() = 0.0;
    mesh.quad(ring[1][s], ring[1][t], ring[3][t], ring[3][s], out);
    mesh.quad(ring[0][s], ring[0][t], ring[2][t], ring[2][s], -out);
    mesh.quad(ring[0][s], ring[0][t], ring[1][t], ring[1][s], -up);
    mesh.quad(ring[2][s], ring[2][t], ring[3][t], ring[3][s], up);
  }
}

void addPrism(MeshBuilder& mesh, const PrismSection& profile, const Eigen::Vector3d& origin,
              const Eigen::Vector3d& u, const Eigen::Vector3d& v, double w0, double w1) {
  const Eigen::Vector3d w = u.cross(v);
  std::vector<std::uint32_t> low, high;
  for (const Eigen::Vector2d& p : profile.points) {
    low.push_back(mesh.vertex(origin + p.x() * u + p.y() * v + w0 * w));
    high.push_back(mesh.vertex(origin + p.x() * u + p.y() * v + w1 * w));
  }
  for (const auto& t : profile.triangles) {
    mesh.triangle(low[t[0]], low[t[1]], low[t[2]], -w);
    mesh.triangle(high[t[0]], high[t[1]], high[t[2]], w);
  }
  const std::size_t n = profile.outline.size();
  for (std::size_t k = 0; k < n; ++k) {
    const int a = profile.outline[k], b = profile.outline[(k + 1) % n];
    const Eigen::Vector2d d = profile.points[b] - profile.points[a];  // outward: d turned right
    mesh.quad(low[a], low[b], high[b], high[a], d.y() * u - d.x() * v);
  }
}

}  // namespace gtbake
