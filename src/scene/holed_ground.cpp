#include "scene/holed_ground.h"

#include <cmath>
#include <string>

#include "common/error.h"

namespace gtbake {
namespace {

// Points of one cell side from `lo` to `hi` (excluded): the end points are copied, not computed,
// so every cell sharing a corner or a side produces bit-identical coordinates.
double sidePoint(double lo, double hi, int j, int m, const std::vector<double>& offsets) {
  if (j == 0) return lo;
  if (j == m) return hi;
  return 0.5 * (lo + hi) + offsets[j];
}

}  // namespace

std::vector<HoleRim> addHoledGround(MeshBuilder& mesh, int cells_x, int cells_z, double cell,
                                    int segments, const std::vector<GroundHole>& holes,
                                    double extent) {
  if (segments <= 0 || segments % 8 != 0) {
    throw Error("holed ground: the curve segments must be a positive multiple of 8, got " +
                std::to_string(segments));
  }
  const double pi = std::acos(-1.0);
  const int m = segments / 4;  // points per cell side
  const double half = 0.5 * cell;
  const double step = 2.0 * pi / segments;
  // o_j = h tan(−π/4 + jΔ): where the ray at angle θ_j meets the side; exactly antisymmetric.
  std::vector<double> offsets(m + 1, 0.0);
  for (int j = 0; j < m / 2; ++j) {
    offsets[j] = half * std::tan(-0.25 * pi + j * step);
    offsets[m - j] = -offsets[j];
  }
  std::vector<double> xline(cells_x + 1);
  std::vector<double> zline(cells_z + 1);
  for (int i = 0; i <= cells_x; ++i) xline[i] = (i - 0.5 * cells_x) * cell;
  for (int i = 0; i <= cells_z; ++i) zline[i] = (i - 0.5 * cells_z) * cell;

  // Square loop of cell (ix, iz) in the order of θ_k, and the same points as local offsets.
  const auto squareLoop = [&](int ix, int iz, std::vector<Eigen::Vector3d>* local) {
    const double x0 = xline[ix], x1 = xline[ix + 1], z0 = zline[iz], z1 = zline[iz + 1];
    std::vector<std::uint32_t> loop;
    local->clear();
    for (int q = 0; q < m; ++q) {
      loop.push_back(mesh.vertex({x1, 0.0, sidePoint(z0, z1, q, m, offsets)}));
      local->emplace_back(half, 0.0, q == 0 ? -half : offsets[q]);
    }
    for (int q = 0; q < m; ++q) {
      loop.push_back(mesh.vertex({sidePoint(x0, x1, m - q, m, offsets), 0.0, z1}));
      local->emplace_back(q == 0 ? half : offsets[m - q], 0.0, half);
    }
    for (int q = 0; q < m; ++q) {
      loop.push_back(mesh.vertex({x0, 0.0, sidePoint(z0, z1, m - q, m, offsets)}));
      local->emplace_back(-half, 0.0, q == 0 ? half : offsets[m - q]);
    }
    for (int q = 0; q < m; ++q) {
      loop.push_back(mesh.vertex({sidePoint(x0, x1, q, m, offsets), 0.0, z0}));
      local->emplace_back(q == 0 ? -half : offsets[q], 0.0, -half);
    }
    return loop;
  };

  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  std::vector<HoleRim> rims(holes.size());
  std::vector<Eigen::Vector3d> local;
  for (int iz = 0; iz < cells_z; ++iz) {
    for (int ix = 0; ix < cells_x; ++ix) {
      const std::vector<std::uint32_t> square = squareLoop(ix, iz, &local);
      const Eigen::Vector3d centre(0.5 * (xline[ix] + xline[ix + 1]), 0.0,
                                   0.5 * (zline[iz] + zline[iz + 1]));
      int hole = -1;
      for (std::size_t h = 0; h < holes.size(); ++h) {
        if (holes[h].cell_x == ix && holes[h].cell_z == iz) hole = static_cast<int>(h);
      }
      if (hole < 0) {
        const std::uint32_t c = mesh.vertex(centre);
        for (int k = 0; k < segments; ++k) {
          mesh.triangle(c, square[k], square[(k + 1) % segments], up);
        }
        continue;
      }
      const GroundHole& g = holes[hole];
      HoleRim& rim = rims[hole];
      rim.centre = centre;
      for (int k = 0; k < segments; ++k) {
        const double theta = -0.25 * pi + k * step;
        const Eigen::Vector3d offset =
            g.circle ? Eigen::Vector3d(g.half_x * std::cos(theta), 0.0, g.half_x * std::sin(theta))
                     : Eigen::Vector3d(local[k].x() * g.half_x / half, 0.0,
                                       local[k].z() * g.half_z / half);
        rim.loop.push_back(mesh.vertex(centre + offset));
      }
      for (int k = 0; k < segments; ++k) {
        const int n = (k + 1) % segments;
        mesh.quad(square[k], square[n], rim.loop[n], rim.loop[k], up);
      }
    }
  }

  // Outer boundary of the block, counter-clockwise in θ, then rings scaled ×2 out to `extent`.
  std::vector<Eigen::Vector3d> boundary;
  for (int ix = 0; ix < cells_x; ++ix) {
    for (int q = 0; q < m; ++q)
      boundary.emplace_back(sidePoint(xline[ix], xline[ix + 1], q, m, offsets), 0.0, zline[0]);
  }
  for (int iz = 0; iz < cells_z; ++iz) {
    for (int q = 0; q < m; ++q)
      boundary.emplace_back(xline[cells_x], 0.0,
                            sidePoint(zline[iz], zline[iz + 1], q, m, offsets));
  }
  for (int ix = cells_x; ix-- > 0;) {
    for (int q = 0; q < m; ++q)
      boundary.emplace_back(sidePoint(xline[ix], xline[ix + 1], m - q, m, offsets), 0.0,
                            zline[cells_z]);
  }
  for (int iz = cells_z; iz-- > 0;) {
    for (int q = 0; q < m; ++q)
      boundary.emplace_back(xline[0], 0.0, sidePoint(zline[iz], zline[iz + 1], m - q, m, offsets));
  }
  std::vector<std::uint32_t> inner;
  for (const auto& p : boundary) inner.push_back(mesh.vertex(p));
  const double smallest_half = 0.5 * cell * std::min(cells_x, cells_z);
  double scale = 1.0;
  while (scale * smallest_half < extent) {
    scale = std::min(2.0 * scale, extent / smallest_half);
    std::vector<std::uint32_t> outer;
    for (const auto& p : boundary) outer.push_back(mesh.vertex(scale * p));
    for (std::size_t k = 0; k < inner.size(); ++k) {
      const std::size_t n = (k + 1) % inner.size();
      mesh.quad(inner[k], inner[n], outer[n], outer[k], up);
    }
    inner = outer;
  }
  return rims;
}

void addBowl(MeshBuilder& mesh, const HoleRim& rim, double R, double h, int segments) {
  const double pi = std::acos(-1.0);
  const double step = 2.0 * pi / segments;
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
        const double theta = -0.25 * pi + k * step;
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
