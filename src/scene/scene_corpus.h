// The scene corpus: twelve scene types in seeded variants (docs/scenes.md, "The corpus").
//
// The seven classic types (procedural_scenes.h) and five more that stress ambient occlusion
// differently: interiors (a room open on one side, with furniture-like boxes), colonnades and
// arcades, rock piles, thin geometry (blades, slats, railings) and mechanical parts. Variant 0 of
// a classic type is the classic scene (clutter and terrain with the corpus seed); variants 1, 2, …
// draw their parameters from counter `variant` of the type's own random stream, so every scene is
// a pure function of (type, variant, seed). Every scene is named "<type>_<variant>" and carries
// its type (written into the glTF, read back by the sweep).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/rng.h"
#include "scene/mesh_builder.h"
#include "scene/scene.h"

namespace gtbake {

// Uniform draws for one scene variant: d(k) is the k-th number in [0, 1) of counter `variant` of
// the random stream (seed, stream); d.in(k, lo, hi) maps it to [lo, hi).
class VariantDraws {
 public:
  VariantDraws(std::uint64_t seed, std::uint64_t stream, int variant)
      : rng_(seed, stream), variant_(static_cast<std::uint64_t>(variant)) {}
  double operator()(std::uint32_t k) const { return rng_.uniform4(variant_, k / 4)[k % 4]; }
  double in(std::uint32_t k, double lo, double hi) const { return lo + (hi - lo) * (*this)(k); }

 private:
  CounterRng rng_;
  std::uint64_t variant_;
};

// Variants per type in the default corpus: 12 types × 6 = 72 scenes (docs/scenes.md).
inline constexpr int kCorpusVariants = 6;

// The twelve corpus types in their fixed order: the seven classic ones, then interior, colonnade,
// rocks, thin, mechanical.
const std::vector<std::string>& corpusTypeNames();

// Scene `variant` (≥ 0) of corpus type `type`; throws gtbake::Error for an unknown type.
Scene makeCorpusScene(const std::string& type, int variant, std::uint64_t seed);

// The five new types; `seed` and `variant` pick every parameter (docs/scenes.md lists them).
Scene makeInteriorScene(std::uint64_t seed, int variant);
Scene makeColonnadeScene(std::uint64_t seed, int variant);
Scene makeRocksScene(std::uint64_t seed, int variant);
Scene makeThinScene(std::uint64_t seed, int variant);
Scene makeMechanicalScene(std::uint64_t seed, int variant);

// Building blocks of the new types (outward facing closed solids unless said otherwise).
//
// Upright prism over a profile star-shaped about its origin (points (x, z) in order around it),
// placed at `base` (its bottom centre), `height` tall; caps are fans from the centre.
void addExtrusion(MeshBuilder& mesh, const Eigen::Vector3d& base,
                  const std::vector<Eigen::Vector2d>& profile, double height);
// Upright tube: radii inner < outer, flat annular ends, `segments` sides.
void addTube(MeshBuilder& mesh, const Eigen::Vector3d& base, double inner, double outer,
             double height, int segments);

// A planar polygon for addPrism: its points (each added once, so every triangle using a point
// uses the same vertex), a triangulation of it, and its outline (point indices counter-clockwise,
// every outline point among them and no point of the triangulation on an outline edge).
struct PrismSection {
  std::vector<Eigen::Vector2d> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> outline;
  int add(double x, double y) {
    points.emplace_back(x, y);
    return static_cast<int>(points.size()) - 1;
  }
  void quad(int a, int b, int c, int d) {  // a-b-c-d in order around a convex quad
    triangles.push_back({a, b, c});
    triangles.push_back({a, c, d});
  }
};
// The profile (point p at origin + p.x u + p.y v, u ⟂ v unit) extruded along w = u × v from w0
// to w1 > w0: one closed solid whose caps are the triangulation.
void addPrism(MeshBuilder& mesh, const PrismSection& profile, const Eigen::Vector3d& origin,
              const Eigen::Vector3d& u, const Eigen::Vector3d& v, double w0, double w1);

}  // namespace gtbake
