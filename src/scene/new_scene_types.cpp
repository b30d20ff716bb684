// The five corpus types beyond the classic seven (scene_corpus.h): interior, colonnade, rocks,
// thin, mechanical. Sizes in metres; the parameter ranges are listed in docs/scenes.md.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <tuple>
#include <vector>

#include "common/math_constants.h"
#include "common/rng.h"
#include "scene/procedural_scenes.h"
#include "scene/scene_corpus.h"

namespace gtbake {
namespace {

// Random streams of the new types (one each, so they never share draws).
constexpr std::uint64_t kInteriorStream = 0x696e7472;    // "intr"
constexpr std::uint64_t kColonnadeStream = 0x636f6c6e;   // "coln"
constexpr std::uint64_t kRocksStream = 0x726f636b;       // "rock"
constexpr std::uint64_t kThinStream = 0x7468696e;        // "thin"
constexpr std::uint64_t kMechanicalStream = 0x6d656368;  // "mech"
// Segments per turn of the new types' curved parts: they are clutter, not closed-form features.
constexpr int kSegments = 48;

const Eigen::Vector3d kUp = Eigen::Vector3d::UnitY();
const Eigen::Vector3d kX = Eigen::Vector3d::UnitX();
const Eigen::Vector3d kZ = Eigen::Vector3d::UnitZ();

// The camera of the ground-based new types: as clutter's, looking down at the origin.
PerspectiveCamera groundCamera(double scale) {
  return lookAt(scale * Eigen::Vector3d(0.0, 4.3, 4.9), scale * Eigen::Vector3d(0.0, 0.3, 0.0), kUp,
                kFov);
}

// A table: a top slab on four legs.
void addTable(MeshBuilder& mesh, const Eigen::Vector3d& at, double hx, double hz, double height,
              double yaw) {
  const Eigen::Vector3d ax(std::cos(yaw), 0.0, -std::sin(yaw)),
      az(std::sin(yaw), 0.0, std::cos(yaw));
  constexpr double kLeg = 0.03, kTop = 0.025;
  addOrientedBox(mesh, at + (height - kTop) * kUp, ax, kUp, az, {hx, kTop, hz});
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d corner = at + ((k & 1) ? 1.0 : -1.0) * (hx - 2 * kLeg) * ax +
                                   ((k & 2) ? 1.0 : -1.0) * (hz - 2 * kLeg) * az;
    addBox(mesh, corner, kLeg, kLeg, height - 2.0 * kTop, yaw);
  }
}

// The floor rectangle a piece of furniture covers: centre, half-extents along its own axes
// (addBox's, turned by yaw about +Y).
struct Footprint {
  double x, z, hx, hz, yaw;
};

// Whether a and b are more than `gap` apart along one of their four edge directions (two convex
// rectangles that do not overlap are separated along one of them).
bool apart(const Footprint& a, const Footprint& b, double gap) {
  const auto reach = [](const Footprint& f, const Eigen::Vector2d& n) {
    return f.hx * std::abs(n.dot(Eigen::Vector2d(std::cos(f.yaw), -std::sin(f.yaw)))) +
           f.hz * std::abs(n.dot(Eigen::Vector2d(std::sin(f.yaw), std::cos(f.yaw))));
  };
  for (const Footprint* f : {&a, &b}) {
    for (const double angle : {f->yaw, f->yaw + 0.5 * kPi}) {
      const Eigen::Vector2d n(std::cos(angle), -std::sin(angle));
      const double distance = std::abs(n.dot(Eigen::Vector2d(b.x - a.x, b.z - a.z)));
      if (distance > reach(a, n) + reach(b, n) + gap) return true;
    }
  }
  return false;
}

// Cabinets against the back wall (0.4–0.6 m deep, with gaps between them) and a sideboard along
// each side wall, between the cabinets' zone and the opening; returns their footprints.
std::vector<Footprint> addCabinets(MeshBuilder& mesh, const VariantDraws& u, double W, double D,
                                   double H) {
  std::vector<Footprint> placed;
  double x = -0.5 * W + 0.05;
  for (std::uint32_t k = 0; x < 0.5 * W - 0.5; ++k) {
    const double half = u.in(4 + k, 0.25, 0.7), depth = u.in(12 + k, 0.2, 0.3);
    const double height = u.in(20 + k, 0.5, 0.9) * H;
    if (x + 2.0 * half > 0.5 * W - 0.05) break;
    placed.push_back({x + half, -0.5 * D + depth + 0.02, half, depth, 0.0});
    addBox(mesh, {placed.back().x, 0.0, placed.back().z}, half, depth, height, 0.0);
    x += 2.0 * half + u.in(28 + k, 0.05, 0.6);
  }
  const double lo = -0.5 * D + 0.7, hi = 0.5 * D - 0.5;  // clear of the cabinets (≤ 0.62 deep)
  for (int side = 0; side < 2; ++side) {
    const double half = u.in(36 + side, 0.6, 1.2), depth = 0.25;
    const double sx = (side == 0 ? -1.0 : 1.0) * (0.5 * W - depth - 0.02);
    placed.push_back({sx, lo + half + u(38 + side) * (hi - lo - 2.0 * half), depth, half, 0.0});
    addBox(mesh, {sx, 0.0, placed.back().z}, depth, half, u.in(40 + side, 0.7, 1.1), 0.0);
  }
  return placed;
}

// Tables in the middle, a chair (seat box and back slab) in front of each; a table and its chair
// are left out where they would come within 5 cm of furniture already placed.
void addTablesAndChairs(MeshBuilder& mesh, const VariantDraws& u, double W, double D,
                        std::vector<Footprint>& placed) {
  const int tables = 1 + static_cast<int>(3.0 * u(44));
  for (int k = 0; k < tables; ++k) {
    const double tx = (k + 0.5) / tables * (W - 2.4) - 0.5 * (W - 2.4);
    const double tz = u.in(45 + k, -0.25, 0.05) * D;
    const double yaw = u.in(50 + k, -0.3, 0.3);
    const double hx = u.in(55 + k, 0.35, 0.6), hz = u.in(60 + k, 0.3, 0.45);
    // The seat (turned by yaw, reaching 0.25 from its centre) 5 cm in front of the table.
    const double reach = hz * std::cos(yaw) + hx * std::abs(std::sin(yaw));
    const Eigen::Vector3d seat(tx + 0.15, 0.0, tz + reach + 0.3);
    const Footprint group[3] = {{tx, tz, hx, hz, yaw},
                                {seat.x(), seat.z(), 0.2, 0.2, yaw},
                                {seat.x(), seat.z() + 0.18, 0.2, 0.02, 0.0}};
    const bool clear = std::all_of(placed.begin(), placed.end(), [&](const Footprint& f) {
      return apart(f, group[0], 0.05) && apart(f, group[1], 0.05) && apart(f, group[2], 0.05);
    });
    if (!clear) continue;
    placed.insert(placed.end(), std::begin(group), std::end(group));
    addTable(mesh, {tx, 0.0, tz}, hx, hz, 0.75, yaw);
    addBox(mesh, seat, 0.2, 0.2, 0.45, yaw);
    addOrientedBox(mesh, seat + Eigen::Vector3d(0.0, 0.7, 0.18), kX, kUp, kZ, {0.2, 0.25, 0.02});
  }
}

// A polygon fanned from `centre`, which sees every outline point (the L shapes here: a point of
// the square both bars share).
PrismSection fanSection(const std::vector<Eigen::Vector2d>& outline,
                        const Eigen::Vector2d& centre) {
  PrismSection p;
  const int middle = p.add(centre.x(), centre.y());
  for (const Eigen::Vector2d& q : outline) p.outline.push_back(p.add(q.x(), q.y()));
  for (std::size_t k = 0; k < p.outline.size(); ++k) {
    p.triangles.push_back({middle, p.outline[k], p.outline[(k + 1) % p.outline.size()]});
  }
  return p;
}

// An arcade in the (x, y) plane: `piers` piers of half-width r centred at x0 + k·spacing, from
// the ground to the springing line, semicircular arches of radius spacing/2 − r between them and
// the wall above them up to `top`: one polygon, its outline running along the ground, up the
// piers and over the arches, then back along the top.
struct ArcadeLayout {
  int piers;
  double x0, spacing, r, springing, top;
};

// Segments of each arch's intrados (a semicircle): kSegments per full turn.
constexpr int kArchSteps = kSegments / 2;

// The points shared between the piers, the arches and the wall: per pier, its foot corners,
// its springing corners and centre, its top, and the points on its centre line where the rays
// from both neighbouring arches' centres meet it (side[k][0] = the springing centre).
struct ArcadePoints {
  std::vector<int> foot_l, foot_r, spring_l, spring_r, top;
  std::vector<std::vector<int>> side;
  int top_left = 0, top_right = 0;
};

ArcadePoints arcadePiers(PrismSection& p, const ArcadeLayout& g, int corner_step) {
  ArcadePoints q;
  for (int k = 0; k < g.piers; ++k) {
    const double x = g.x0 + k * g.spacing;
    q.foot_l.push_back(p.add(x - g.r, 0.0));
    q.foot_r.push_back(p.add(x + g.r, 0.0));
    q.spring_l.push_back(p.add(x - g.r, g.springing));
    q.spring_r.push_back(p.add(x + g.r, g.springing));
    q.side.push_back({p.add(x, g.springing)});
    for (int j = 1; j <= corner_step; ++j) {
      q.side[k].push_back(p.add(x, g.springing + 0.5 * g.spacing * std::tan(kPi * j / kArchSteps)));
    }
    q.top.push_back(p.add(x, g.top));
    // The pier below the springing line: a pentagon (its top edge split at the centre).
    p.triangles.push_back({q.foot_l[k], q.foot_r[k], q.spring_r[k]});
    p.triangles.push_back({q.foot_l[k], q.spring_r[k], q.side[k][0]});
    p.triangles.push_back({q.foot_l[k], q.side[k][0], q.spring_l[k]});
  }
  q.top_left = p.add(g.x0 - g.r, g.top);
  q.top_right = p.add(g.x0 + (g.piers - 1) * g.spacing + g.r, g.top);
  return q;
}

// Arch k (between piers k and k + 1) and the wall above it: each half is a strip of quads
// between the intrados and the pier's centre line along the rays from the arch's centre, up to
// the last ray below the top corner, then a fan from that corner; the crown triangle joins the
// halves. Returns the intrados points, right (angle 0) to left.
std::vector<int> addArch(PrismSection& p, const ArcadeLayout& g, const ArcadePoints& q, int k,
                         int corner_step) {
  const double centre = g.x0 + (k + 0.5) * g.spacing, a = 0.5 * g.spacing - g.r;
  std::vector<int> arc(kArchSteps + 1);
  arc.front() = q.spring_l[k + 1];
  arc.back() = q.spring_r[k];
  for (int j = 1; j < kArchSteps; ++j) {
    const double angle = kPi * j / kArchSteps;
    arc[j] = p.add(centre + a * std::cos(angle), g.springing + a * std::sin(angle));
  }
  for (int half = 0; half < 2; ++half) {
    const auto at = [&](int m) { return arc[half == 0 ? m : kArchSteps - m]; };
    const std::vector<int>& side = q.side[half == 0 ? k + 1 : k];
    const int corner = q.top[half == 0 ? k + 1 : k];
    for (int m = 0; m < corner_step; ++m) p.quad(at(m), at(m + 1), side[m + 1], side[m]);
    p.triangles.push_back({side[corner_step], corner, at(corner_step)});
    for (int m = corner_step; m < kArchSteps / 2; ++m) {
      p.triangles.push_back({corner, at(m), at(m + 1)});
    }
  }
  p.triangles.push_back({q.top[k + 1], q.top[k], arc[kArchSteps / 2]});
  return arc;
}

PrismSection arcadeProfile(const ArcadeLayout& g) {
  // The last ray from an arch's centre that meets the pier's centre line below the top.
  const double corner_angle = std::atan2(g.top - g.springing, 0.5 * g.spacing);
  int corner_step = 0;
  while (kPi * (corner_step + 1) / kArchSteps < corner_angle) ++corner_step;
  PrismSection p;
  const ArcadePoints q = arcadePiers(p, g, corner_step);
  for (int k = 0; k < g.piers; ++k) {
    p.outline.insert(p.outline.end(), {q.foot_l[k], q.foot_r[k], q.spring_r[k]});
    if (k + 1 == g.piers) break;
    const std::vector<int> arc = addArch(p, g, q, k, corner_step);
    p.outline.insert(p.outline.end(), arc.rbegin() + 1, arc.rend());
  }
  // The wall above the end piers: fans from their outer springing corners.
  const int last = g.piers - 1;
  for (const auto& [from, pier, outer] : {std::tuple{q.spring_l[0], 0, q.top_left},
                                          std::tuple{q.spring_r[last], last, q.top_right}}) {
    const std::vector<int>& side = q.side[pier];
    for (std::size_t j = 0; j + 1 < side.size(); ++j) {
      p.triangles.push_back({from, side[j], side[j + 1]});
    }
    p.triangles.push_back({from, side.back(), q.top[pier]});
    p.triangles.push_back({from, q.top[pier], outer});
  }
  p.outline.push_back(q.top_right);
  p.outline.insert(p.outline.end(), q.top.rbegin(), q.top.rend());
  p.outline.insert(p.outline.end(), {q.top_left, q.spring_l[0]});
  return p;
}

}  // namespace

Scene makeInteriorScene(std::uint64_t seed, int variant) {
  // A room W × D × H with floor, ceiling, back and side walls, open at z = +D/2 (the camera looks
  // in from just inside it); cabinets along the back and side walls, tables and chairs inside.
  const VariantDraws u(seed, kInteriorStream, variant);
  const double W = u.in(0, 4.0, 7.0), D = u.in(1, 4.0, 7.0), H = u.in(2, 2.4, 3.4);
  MeshBuilder mesh;
  std::uint32_t c[8];
  for (int k = 0; k < 8; ++k) {
    c[k] = mesh.vertex(
        {(k & 1) ? 0.5 * W : -0.5 * W, (k & 4) ? H : 0.0, (k & 2) ? 0.5 * D : -0.5 * D});
  }
  const Eigen::Vector3d inside(0.0, 0.5 * H, 0.0);
  const auto in = [&](std::uint32_t a, std::uint32_t b) -> Eigen::Vector3d {
    return inside - 0.5 * (mesh.position(a) + mesh.position(b));
  };
  mesh.quad(c[0], c[1], c[3], c[2], in(c[0], c[3]));  // floor
  mesh.quad(c[4], c[5], c[7], c[6], in(c[4], c[7]));  // ceiling
  mesh.quad(c[0], c[1], c[5], c[4], in(c[0], c[5]));  // back, z = −D/2
  mesh.quad(c[0], c[2], c[6], c[4], in(c[0], c[6]));  // x = −W/2
  mesh.quad(c[1], c[3], c[7], c[5], in(c[1], c[7]));  // x = +W/2
  std::vector<Footprint> placed = addCabinets(mesh, u, W, D, H);
  addTablesAndChairs(mesh, u, W, D, placed);
  const Eigen::Vector3d eye(0.1 * W, 0.62 * H, 0.5 * D - 0.05);
  return mesh.finish("interior", lookAt(eye, {0.0, 0.15 * H, -0.3 * D}, kUp, kFov));
}

Scene makeColonnadeScene(std::uint64_t seed, int variant) {
  // A row of columns along x in front of a back wall, carrying either a flat roof slab (a
  // portico) or semicircular arches with a wall above them (an arcade); even variants are
  // porticoes, odd ones arcades. No two pieces overlap (docs/scenes.md, "Pieces that touch").
  const VariantDraws u(seed, kColonnadeStream, variant);
  const int columns = 4 + static_cast<int>(4.0 * u(0));
  const double spacing = u.in(1, 0.9, 1.6), radius = u.in(2, 0.1, 0.25) * spacing;
  const double height = u.in(3, 1.8, 3.0), depth = u.in(4, 0.8, 2.0);  // portico depth
  const bool arcade = variant % 2 == 1;
  MeshBuilder mesh;
  addFlatGround(mesh, 8.0);
  const double span = (columns - 1) * spacing;
  const double x0 = -0.5 * span;
  const double slab = 0.2 * spacing;
  const double half_x = 0.5 * span + 2.0 * radius;
  if (arcade) {
    // Back wall behind the arcade, clear of it.
    addOrientedBox(mesh, {0.0, 0.5 * (height + slab), -depth}, kX, kUp, kZ,
                   {half_x, 0.5 * (height + slab), 0.1});
    addPrism(mesh,
             arcadeProfile({columns, x0, spacing, radius, height - 0.5 * spacing, height + slab}),
             Eigen::Vector3d::Zero(), kX, kUp, -radius, radius);
  } else {
    // Round columns standing on the ground, their tops against the slab's underside.
    for (int k = 0; k < columns; ++k) {
      addCylinder(mesh, {x0 + k * spacing, 0.0, 0.0}, radius, height, kSegments);
    }
    // The back wall (0.2 thick, centred at z = −depth, up to the slab's top) and the roof slab
    // (from the wall's back face to 2 radii in front of the columns) as one solid: an L in the
    // (z, y) plane.
    const double back = -depth - 0.1, face = -depth + 0.1, front = 2.0 * radius;
    const double top = height + slab;
    addPrism(
        mesh,
        fanSection(
            {{back, 0.0}, {face, 0.0}, {face, height}, {front, height}, {front, top}, {back, top}},
            {-depth, height + 0.5 * slab}),
        Eigen::Vector3d::Zero(), kZ, kUp, -half_x, half_x);
  }
  // Looking down 37° (more than half the field of view): rays over the wall meet the ground.
  const double distance = 1.6 * height + 0.5 * span;
  return mesh.finish("colonnade",
                     lookAt({0.25 * span, 0.35 * height + 0.75 * distance, distance - 0.3 * depth},
                            {0.0, 0.35 * height, -0.3 * depth}, kUp, kFov));
}

Scene makeRocksScene(std::uint64_t seed, int variant) {
  // A pile of rocks: squashed spheres with a radial relief of three random cosine lobes, partly
  // sunk into the ground and partly stacked (they may interpenetrate, as rubble does).
  const VariantDraws u(seed, kRocksStream, variant);
  const int rocks = 8 + static_cast<int>(16.0 * u(0));
  const double spread = u.in(1, 1.2, 2.6), relief = u.in(2, 0.1, 0.3);
  MeshBuilder mesh;
  addFlatGround(mesh, 6.0);
  std::vector<Eigen::Vector4d> placed;  // centre, radius
  for (int k = 0; k < rocks; ++k) {
    const std::uint32_t b = 8 + 16 * static_cast<std::uint32_t>(k);
    const double r = u.in(b, 0.2, 0.8) * (1.0 - 0.4 * k / rocks);
    const double angle = 2.0 * kPi * u(b + 1), dist = spread * std::sqrt(u(b + 2));
    Eigen::Vector3d centre(dist * std::cos(angle), 0.2 * r, dist * std::sin(angle));
    for (const Eigen::Vector4d& p : placed) {  // rest on the rocks below (roughly)
      const double gap = std::hypot(p.x() - centre.x(), p.z() - centre.z());
      const double reach = 0.8 * (p.w() + r);
      if (gap < reach) {
        centre.y() = std::max(centre.y(), p.y() + std::sqrt(reach * reach - gap * gap));
      }
    }
    placed.emplace_back(centre.x(), centre.y(), centre.z(), r);
    Eigen::Vector3d lobes[3];
    double phase[3];
    for (int l = 0; l < 3; ++l) {
      lobes[l] =
          Eigen::Vector3d(u(b + 3 + 3 * l) - 0.5, u(b + 4 + 3 * l) - 0.5, u(b + 5 + 3 * l) - 0.5)
              .normalized();
      phase[l] = 2.0 * kPi * u(b + 12 + l);
    }
    const auto radius = [&](const Eigen::Vector3d& d) {
      double s = 0.0;
      for (int l = 0; l < 3; ++l) s += std::cos(3.0 * d.dot(lobes[l]) + phase[l]);
      return r * (1.0 + relief * s / 3.0);
    };
    const int rings = kSegments / 4;
    const Eigen::Vector3d squash(1.0, 0.7, 1.0);
    const auto point = [&](int ring, int s) {
      const double polar = kPi * ring / rings, azimuth = 2.0 * kPi * s / (kSegments / 2);
      const Eigen::Vector3d d(std::sin(polar) * std::cos(azimuth), -std::cos(polar),
                              std::sin(polar) * std::sin(azimuth));
      return mesh.vertex(centre + radius(d) * d.cwiseProduct(squash));
    };
    for (int ring = 0; ring < rings; ++ring) {
      for (int s = 0; s < kSegments / 2; ++s) {
        const int t = (s + 1) % (kSegments / 2);
        const std::uint32_t a = point(ring, s), b1 = point(ring, t), c = point(ring + 1, t),
                            e = point(ring + 1, s);
        mesh.quad(a, b1, c, e, mesh.position(a) + mesh.position(c) - 2.0 * centre);
      }
    }
  }
  return mesh.finish("rocks", groundCamera(0.8 + 0.2 * spread));
}

Scene makeThinScene(std::uint64_t seed, int variant) {
  // Thin geometry on the ground: a patch of grass blades (single two-sided triangles, leaning), a
  // louvre of tilted slats on posts, and a railing of thin posts and rails; the densities, slat
  // tilt and sizes vary.
  const VariantDraws u(seed, kThinStream, variant);
  MeshBuilder mesh;
  addFlatGround(mesh, 6.0);
  // Blades in x ∈ [−2.6, 0], z ∈ [−1.5, 2]: width 2–5 cm, height 0.15–0.6 m.
  const int blades = 150 + static_cast<int>(450.0 * u(0));
  const CounterRng blade_rng(seed * 16 + static_cast<std::uint64_t>(variant), kThinStream + 1);
  const double blade_height = u.in(1, 0.15, 0.6);
  for (int k = 0; k < blades; ++k) {
    const auto a = blade_rng.uniform4(static_cast<std::uint64_t>(k), 0);
    const Eigen::Vector3d root(-2.6 + 2.6 * a[0], 0.0, -1.5 + 3.5 * a[1]);
    const double yaw = 2.0 * kPi * a[2], w = 0.01 + 0.015 * a[3];
    const Eigen::Vector3d side(std::cos(yaw), 0.0, std::sin(yaw));
    const Eigen::Vector3d lean = 0.3 * blade_height * (a[2] - 0.5) * side.cross(kUp);
    const Eigen::Vector3d tip = root + blade_height * (0.6 + 0.8 * a[3]) * kUp + lean;
    mesh.triangle(mesh.vertex(root - w * side), mesh.vertex(root + w * side), mesh.vertex(tip),
                  side.cross(kUp));
  }
  // Louvre: slats along x between two posts at x ∈ [0.3, 2.6], z = −1.2, tilted about x.
  const int slats = 6 + static_cast<int>(8.0 * u(2));
  const double tilt = u.in(3, 0.2, 1.2), pitch = u.in(4, 0.08, 0.2), thick = 0.012;
  for (double px : {0.3, 2.6}) addBox(mesh, {px, 0.0, -1.2}, 0.03, 0.03, pitch * slats + 0.3, 0.0);
  const Eigen::Vector3d along = kX, across(0.0, std::sin(tilt), std::cos(tilt));
  for (int k = 0; k < slats; ++k) {
    addOrientedBox(mesh, {1.45, 0.25 + pitch * k, -1.2}, along, across, along.cross(across),
                   {1.12, 0.6 * pitch, thick});
  }
  // Railing along z at x = 1.6, z ∈ [−0.4, 2.4]: posts 2–4 cm, two rails.
  const int posts = 6 + static_cast<int>(10.0 * u(5));
  const double post = u.in(6, 0.01, 0.02), rail_height = u.in(7, 0.7, 1.1);
  for (int k = 0; k < posts; ++k) {
    addBox(mesh, {1.6, 0.0, -0.4 + 2.8 * k / (posts - 1)}, post, post, rail_height, 0.0);
  }
  // The middle rail against the posts' +x side, the top rail on the posts' tops.
  addOrientedBox(mesh, {1.6 + post + 0.025, 0.5 * rail_height, 1.0}, kX, kUp, kZ,
                 {0.025, 0.02, 1.45});
  addOrientedBox(mesh, {1.6, rail_height + 0.02, 1.0}, kX, kUp, kZ, {0.025, 0.02, 1.45});
  return mesh.finish("thin", groundCamera(0.85));
}

Scene makeMechanicalScene(std::uint64_t seed, int variant) {
  // Machine parts on the ground: two meshing spur gears on a base plate, a tube, hexagon bolts
  // and an L bracket; tooth counts and sizes vary.
  const VariantDraws u(seed, kMechanicalStream, variant);
  MeshBuilder mesh;
  addFlatGround(mesh, 6.0);
  addBox(mesh, {-0.6, 0.0, 0.0}, 1.6, 1.1, 0.1, 0.0);  // base plate
  const double module = u.in(0, 0.05, 0.1);            // tooth size, m
  const int teeth[2] = {12 + static_cast<int>(12.0 * u(1)), 8 + static_cast<int>(8.0 * u(2))};
  const double width = u.in(3, 0.1, 0.35);
  double x = -1.5, centre[2], tip[2];
  for (int g = 0; g < 2; ++g) {
    const double pitch_r = 0.5 * module * teeth[g];
    std::vector<Eigen::Vector2d> profile;  // four points per tooth: root, flank, flank, root
    // Turned so that the first gear shows a gap's middle to the second (angle 0, +x) and the
    // second a tooth's middle to the first (angle π).
    const double step = 2.0 * kPi / teeth[g], phase = g == 0 ? 0.1 * step : kPi - 0.4 * step;
    for (int t = 0; t < teeth[g]; ++t) {
      const double a = t * step + phase;
      const double radii[4] = {pitch_r - 1.25 * module, pitch_r + module, pitch_r + module,
                               pitch_r - 1.25 * module};
      const double at[4] = {a, a + 0.3 * step, a + 0.5 * step, a + 0.8 * step};
      for (int k = 0; k < 4; ++k) {
        profile.emplace_back(radii[k] * std::cos(at[k]), -radii[k] * std::sin(at[k]));
      }
    }
    x += pitch_r;
    centre[g] = x;
    tip[g] = pitch_r + module;
    addExtrusion(mesh, {x, 0.1, -0.4}, profile, width);
    addCylinder(mesh, {x, 0.1 + width, -0.4}, 0.3 * pitch_r, 0.15, kSegments / 2);  // hub
    x += pitch_r + 0.5 * module + 0.02;  // teeth engage 1.5 modules deep, clear of each other
  }
  // The tube beside the gears (at z = 0.55), moved along +x until it clears their tips by 5 cm.
  const double tube_r = u.in(4, 0.15, 0.4);
  Eigen::Vector3d tube(0.2, 0.1, 0.55);
  for (int g = 0; g < 2; ++g) {
    const double clear = tip[g] + tube_r + 0.05, across = tube.z() + 0.4;
    if (clear > across) {
      tube.x() = std::max(tube.x(), centre[g] + std::sqrt(clear * clear - across * across));
    }
  }
  addTube(mesh, tube, tube_r * u.in(5, 0.6, 0.85), tube_r, u.in(6, 0.3, 1.0), kSegments);
  std::vector<Eigen::Vector2d> hexagon;
  for (int k = 0; k < 6; ++k) {
    hexagon.emplace_back(std::cos(-k * kPi / 3.0), std::sin(-k * kPi / 3.0));
  }
  const int bolts = 3 + static_cast<int>(4.0 * u(7));
  for (int k = 0; k < bolts; ++k) {
    const double s = u.in(8 + k, 0.04, 0.09);
    std::vector<Eigen::Vector2d> head;
    for (const auto& p : hexagon) head.push_back(s * p);
    const Eigen::Vector3d at(-1.9 + 0.35 * k, 0.1, 0.8);
    addExtrusion(mesh, at, head, 0.7 * s);
    addCylinder(mesh, at + 0.7 * s * kUp, 0.55 * s, u.in(16 + k, 0.1, 0.4), 16);
  }
  // L bracket, one solid: a foot 5 cm thick and an upright 5 cm thick at its −x end, 0.5 wide.
  const double leg = u.in(20, 0.4, 0.8), xl = 1.6 - 0.5 * leg, xr = 1.6 + 0.5 * leg, t = 0.05;
  addPrism(mesh,
           fanSection({{xl, 0.0}, {xr, 0.0}, {xr, t}, {xl + t, t}, {xl + t, leg}, {xl, leg}},
                      {xl + 0.5 * t, 0.5 * t}),
           {0.0, 0.0, -0.9}, kX, kUp, -0.25, 0.25);
  return mesh.finish("mechanical", groundCamera(0.75));
}

}  // namespace gtbake
