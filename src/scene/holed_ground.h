// Ground plane y = 0 with circular and rectangular holes, and the bowls and wells sunk in them.
//
// The plane is a block of square cells centred on the origin, each plain or holding one hole,
// surrounded by geometrically graded rings out to a given extent. Every cell boundary carries the
// same `segments` points (the hole's points projected radially onto the square, so the two loops
// pair up into a strip of quads), which makes neighbouring cells, the rings and the hole rims
// share their vertices exactly: the whole ground is one watertight sheet whose only boundary is
// its outer rectangle.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "scene/mesh_builder.h"

namespace gtbake {

struct GroundHole {
  int cell_x = 0;  // cell column, 0 = most negative x
  int cell_z = 0;  // cell row, 0 = most negative z
  bool circle = true;
  double half_x = 0.5;  // circle: radius; rectangle: half-extent along x
  double half_z = 0.5;  // rectangle: half-extent along z
};

struct HoleRim {
  Eigen::Vector3d centre;           // on y = 0
  std::vector<std::uint32_t> loop;  // `segments` vertices at θ_k = −π/4 + 2πk/segments
};

// `segments` must be a multiple of 8 (so the cell corners are among the projected points); cells
// are `cell` metres wide; holes must fit inside their cell. Returns one rim per hole, in order.
std::vector<HoleRim> addHoledGround(MeshBuilder& mesh, int cells_x, int cells_z, double cell,
                                    int segments, const std::vector<GroundHole>& holes,
                                    double extent);

// Spherical cap of sphere radius R and depth h below the rim (the rim radius is √(h(2R − h))),
// hanging from a circular rim made by addHoledGround with the same `segments`. Rings are spaced
// by the same angle 2π/segments in polar angle, with one vertex at the bottom pole. Faces the
// sphere's centre (the inside of the bowl).
void addBowl(MeshBuilder& mesh, const HoleRim& rim, double R, double h, int segments);

// Vertical walls of depth `depth` below a rim (any hole shape) and a flat floor (a fan from the
// floor's centre). Faces the inside of the well.
void addWell(MeshBuilder& mesh, const HoleRim& rim, double depth);

}  // namespace gtbake
