// Overlap checks of a scene's pieces (docs/scenes.md, "Pieces that touch"): coincident faces and
// crossing surfaces, the two ways separately built pieces can leave a tracer's answer to chance.
//
// A piece is a set of triangles connected through edges that exactly two triangles use (so two
// solids that merely share a welded vertex or edge stay two pieces); it is closed when each of
// its edges is used exactly twice within it.
#pragma once

#include <cstddef>
#include <string>

#include "scene/scene.h"

namespace gtbake::test {

// Distances below this count as touching, m. gtbake's ray offset is up to 0.2 mm for features
// within 10 m (docs/sweep.md §3) and float positions there are exact to 1 µm: faces closer than
// 0.1 mm are decided by each tracer's offset, while every deliberate gap is 1 cm or more.
inline constexpr double kTouchTolerance = 1e-4;
// Coplanar triangles overlap when the overlap exceeds this fraction of the smaller one's area:
// over the corpus, clipping triangles that only touch leaves less than 1e-15 of it (rounding) and
// the smallest real overlap is 1e-7 of it.
inline constexpr double kOverlapFraction = 1e-10;

struct OverlapReport {
  std::size_t pieces = 0;
  std::size_t closed_pieces = 0;
  // Coplanar triangle pairs (every vertex of each within kTouchTolerance of the other's plane)
  // whose interiors overlap (kOverlapFraction), facing the same way: two surfaces in one
  // place, open on the same side, so which one a ray hits and whether the other blocks the ray
  // leaving it is up to the tracer.
  std::size_t coincident = 0;
  // The same, facing opposite ways: a contact sealed between two pieces (a box on the ground, a
  // leg under a table top) that no ray from outside reaches.
  std::size_t contacts = 0;
  // Triangle pairs of two pieces, at least one of them closed, where an edge of one passes
  // through the interior of the other (ends on opposite sides of its plane, crossing point inside
  // it, both by more than kTouchTolerance): surfaces that interpenetrate.
  std::size_t crossings = 0;
  // Pieces lying wholly inside a closed piece (a vertex strictly inside by ray parity) without
  // crossing it.
  std::size_t enclosed = 0;
  std::string first;  // where the first coincident pair or crossing is, for messages
};

OverlapReport findOverlaps(const Scene& scene);

}  // namespace gtbake::test
