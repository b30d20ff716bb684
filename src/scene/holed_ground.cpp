#include "scene/holed_ground.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"
#include "common/math_constants.h"

namespace gtbake {
namespace {

// The block of cells and the points every cell side carries.
struct CellGrid {
  int segments = 0;             // points around each cell square and each rim
  int m = 0;                    // points per cell side, segments / 4
  double half = 0.0;            // half a cell width
  std::vector<double> offsets;  // o_j of point j along a side, from its middle
  std::vector<double> xline;    // cell boundaries along x
  std::vector<double> zline;    // cell boundaries along z
};

// o_j = h tan(−π/4 + jΔ): where the ray from the cell centre at angle θ_j meets the side. Exactly
// antisymmetric (o_{m−j} = −o_j), so both cells sharing a side compute the same points.
CellGrid makeCellGrid(int cells_x, int cells_z, double cell, int segments) {
  CellGrid g;
  g.segments = segments;
  g.m = segments / 4;
  g.half = 0.5 * cell;
  const double step = 2.0 * kPi / segments;
  g.offsets.assign(g.m + 1, 0.0);
  for (int j = 0; j < g.m / 2; ++j) {
    g.offsets[j] = g.half * std::tan(-0.25 * kPi + j * step);
    g.offsets[g.m - j] = -g.offsets[j];
  }
  g.xline.resize(cells_x + 1);
  g.zline.resize(cells_z + 1);
  for (int i = 0; i <= cells_x; ++i) g.xline[i] = (i - 0.5 * cells_x) * cell;
  for (int i = 0; i <= cells_z; ++i) g.zline[i] = (i - 0.5 * cells_z) * cell;
  return g;
}

// Point j of one cell side from `lo` to `hi` (excluded): the end points are copied, not computed,
// so every cell sharing a corner or a side produces bit-identical coordinates.
double sidePoint(const CellGrid& g, double lo, double hi, int j) {
  if (j == 0) return lo;
  if (j == g.m) return hi;
  return 0.5 * (lo + hi) + g.offsets[j];
}

// The square loop of cell (ix, iz) in the order of θ_k, as mesh vertices and as offsets from the
// cell centre (which scale a rectangular hole's rim).
struct CellSquare {
  std::vector<std::uint32_t> loop;
  std::vector<Eigen::Vector3d> local;
};

CellSquare cellSquare(MeshBuilder& mesh, const CellGrid& g, int ix, int iz) {
  const double x0 = g.xline[ix], x1 = g.xline[ix + 1], z0 = g.zline[iz], z1 = g.zline[iz + 1];
  const int m = g.m;
  const double half = g.half;
  CellSquare square;
  for (int q = 0; q < m; ++q) {
    square.loop.push_back(mesh.vertex({x1, 0.0, sidePoint(g, z0, z1, q)}));
    square.local.emplace_back(half, 0.0, q == 0 ? -half : g.offsets[q]);
  }
  for (int q = 0; q < m; ++q) {
    square.loop.push_back(mesh.vertex({sidePoint(g, x0, x1, m - q), 0.0, z1}));
    square.local.emplace_back(q == 0 ? half : g.offsets[m - q], 0.0, half);
  }
  for (int q = 0; q < m; ++q) {
    square.loop.push_back(mesh.vertex({x0, 0.0, sidePoint(g, z0, z1, m - q)}));
    square.local.emplace_back(-half, 0.0, q == 0 ? half : g.offsets[m - q]);
  }
  for (int q = 0; q < m; ++q) {
    square.loop.push_back(mesh.vertex({sidePoint(g, x0, x1, q), 0.0, z0}));
    square.local.emplace_back(q == 0 ? -half : g.offsets[q], 0.0, -half);
  }
  return square;
}

// Index of the hole in cell (ix, iz), or −1 (the last one listed wins).
int holeInCell(const std::vector<GroundHole>& holes, int ix, int iz) {
  int hole = -1;
  for (std::size_t h = 0; h < holes.size(); ++h) {
    if (holes[h].cell_x == ix && holes[h].cell_z == iz) hole = static_cast<int>(h);
  }
  return hole;
}

// A plain cell: a fan from its centre to its square.
void addPlainCell(MeshBuilder& mesh, const CellSquare& square, const Eigen::Vector3d& centre) {
  const std::uint32_t c = mesh.vertex(centre);
  const std::size_t n = square.loop.size();
  for (std::size_t k = 0; k < n; ++k) {
    mesh.triangle(c, square.loop[k], square.loop[(k + 1) % n], Eigen::Vector3d::UnitY());
  }
}

// A cell with a hole: the rim (a circle, or the square scaled to the rectangle) paired point for
// point with the cell's square by a strip of quads. Returns the rim.
HoleRim addHoleCell(MeshBuilder& mesh, const CellGrid& g, const CellSquare& square,
                    const Eigen::Vector3d& centre, const GroundHole& hole) {
  const double step = 2.0 * kPi / g.segments;
  HoleRim rim;
  rim.centre = centre;
  for (int k = 0; k < g.segments; ++k) {
    const double theta = -0.25 * kPi + k * step;
    const Eigen::Vector3d offset =
        hole.circle
            ? Eigen::Vector3d(hole.half_x * std::cos(theta), 0.0, hole.half_x * std::sin(theta))
            : Eigen::Vector3d(square.local[k].x() * hole.half_x / g.half, 0.0,
                              square.local[k].z() * hole.half_z / g.half);
    rim.loop.push_back(mesh.vertex(centre + offset));
  }
  for (int k = 0; k < g.segments; ++k) {
    const int n = (k + 1) % g.segments;
    mesh.quad(square.loop[k], square.loop[n], rim.loop[n], rim.loop[k], Eigen::Vector3d::UnitY());
  }
  return rim;
}

// The block's outer boundary, counter-clockwise in θ, through every cell side point.
std::vector<Eigen::Vector3d> blockBoundary(const CellGrid& g) {
  const int cells_x = static_cast<int>(g.xline.size()) - 1;
  const int cells_z = static_cast<int>(g.zline.size()) - 1;
  const int m = g.m;
  std::vector<Eigen::Vector3d> boundary;
  for (int ix = 0; ix < cells_x; ++ix) {
    for (int q = 0; q < m; ++q) {
      boundary.emplace_back(sidePoint(g, g.xline[ix], g.xline[ix + 1], q), 0.0, g.zline[0]);
    }
  }
  for (int iz = 0; iz < cells_z; ++iz) {
    for (int q = 0; q < m; ++q) {
      boundary.emplace_back(g.xline[cells_x], 0.0, sidePoint(g, g.zline[iz], g.zline[iz + 1], q));
    }
  }
  for (int ix = cells_x; ix-- > 0;) {
    for (int q = 0; q < m; ++q) {
      boundary.emplace_back(sidePoint(g, g.xline[ix], g.xline[ix + 1], m - q), 0.0,
                            g.zline[cells_z]);
    }
  }
  for (int iz = cells_z; iz-- > 0;) {
    for (int q = 0; q < m; ++q) {
      boundary.emplace_back(g.xline[0], 0.0, sidePoint(g, g.zline[iz], g.zline[iz + 1], m - q));
    }
  }
  return boundary;
}

// Rings of the boundary scaled ×2 at a time (the last one exactly to `extent`), joined by quads:
// the graded ground from the block out to the world's edge.
void addGradedRings(MeshBuilder& mesh, const std::vector<Eigen::Vector3d>& boundary,
                    double smallest_half, double extent) {
  std::vector<std::uint32_t> inner;
  for (const auto& p : boundary) inner.push_back(mesh.vertex(p));
  const double last = extent / smallest_half;
  double scale = 1.0;
  while (scale * smallest_half < extent) {
    scale = std::min(2.0 * scale, last);
    std::vector<std::uint32_t> outer;
    for (const auto& p : boundary) outer.push_back(mesh.vertex(scale * p));
    for (std::size_t k = 0; k < inner.size(); ++k) {
      const std::size_t n = (k + 1) % inner.size();
      mesh.quad(inner[k], inner[n], outer[n], outer[k], Eigen::Vector3d::UnitY());
    }
    inner = outer;
    // Rounding can leave last · smallest_half a hair below extent (cavity_1 of `gtbake scenes
    // --seed 4504699138998537` then added rings without end): the ring at `last` is the last.
    if (scale == last) break;
  }
}

}  // namespace

std::vector<HoleRim> addHoledGround(MeshBuilder& mesh, int cells_x, int cells_z, double cell,
                                    int segments, const std::vector<GroundHole>& holes,
                                    double extent) {
  if (segments <= 0 || segments % 8 != 0) {
    throw Error("holed ground: the curve segments must be a positive multiple of 8, got " +
                std::to_string(segments));
  }
  const CellGrid grid = makeCellGrid(cells_x, cells_z, cell, segments);
  std::vector<HoleRim> rims(holes.size());
  for (int iz = 0; iz < cells_z; ++iz) {
    for (int ix = 0; ix < cells_x; ++ix) {
      const CellSquare square = cellSquare(mesh, grid, ix, iz);
      const Eigen::Vector3d centre(0.5 * (grid.xline[ix] + grid.xline[ix + 1]), 0.0,
                                   0.5 * (grid.zline[iz] + grid.zline[iz + 1]));
      const int hole = holeInCell(holes, ix, iz);
      if (hole < 0) {
        addPlainCell(mesh, square, centre);
      } else {
        rims[hole] = addHoleCell(mesh, grid, square, centre, holes[hole]);
      }
    }
  }
  addGradedRings(mesh, blockBoundary(grid), 0.5 * cell * std::min(cells_x, cells_z), extent);
  return rims;
}

void addBowl(MeshBuilder& mesh, const HoleRim& rim, double R, double h, int segments) {
  const double step = 2.0 * kPi / segments;
  const Eigen::Vector3d centre = rim.centre + (R - h) * Eigen::Vector3d::UnitY();
  const double rim_polar = std::acos((R - h) / R);  // from the bottom pole up to the rim
  const int rings = std::max(2, static_cast<int>(std::ceil(rim_polar / step)));
  const auto inward = [&](std::uint32_t v) -> Eigen::Vector3d { return centre - mesh.position(v); };
  const std::uint32_t pole = mesh.vertex(centre - R * Eigen::Vector3d::UnitY());
  std::vector<std::uint32_t> previous;
  for (int r = 1; r <= rings; ++r) {
    std::vector<std::uint32_t> ring = rim.loop;
    if (r < rings) {
      const double polar = rim_polar * r / rings;
      for (int k = 0; k < segments; ++k) {
        const double theta = -0.25 * kPi + k * step;
        ring[k] = mesh.vertex(centre + R * Eigen::Vector3d(std::sin(polar) * std::cos(theta),
                                                           -std::cos(polar),
                                                           std::sin(polar) * std::sin(theta)));
      }
    }
    for (int k = 0; k < segments; ++k) {
      const int n = (k + 1) % segments;
      if (r == 1) {
        mesh.triangle(pole, ring[k], ring[n], inward(ring[k]));
      } else {
        mesh.quad(previous[k], previous[n], ring[n], ring[k], inward(ring[k]));
      }
    }
    previous = ring;
  }
}

void addWell(MeshBuilder& mesh, const HoleRim& rim, double depth) {
  const Eigen::Vector3d down = -depth * Eigen::Vector3d::UnitY();
  const std::size_t n = rim.loop.size();
  const std::uint32_t centre = mesh.vertex(rim.centre + down);
  std::vector<std::uint32_t> floor;
  for (std::uint32_t v : rim.loop) floor.push_back(mesh.vertex(mesh.position(v) + down));
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t next = (k + 1) % n;
    Eigen::Vector3d inward =
        2.0 * rim.centre - mesh.position(rim.loop[k]) - mesh.position(rim.loop[next]);
    inward.y() = 0.0;
    mesh.quad(rim.loop[k], rim.loop[next], floor[next], floor[k], inward);
    mesh.triangle(centre, floor[k], floor[next], Eigen::Vector3d::UnitY());
  }
}

}  // namespace gtbake
