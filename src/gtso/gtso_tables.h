// The 3D and 4D GTSO tables: axis mappings, baking, multilinear lookup and a BC4 error proxy.
//
// Logical axes (SPEC §1.4): A (ambient occlusion), beta (angle between bent normal and wr),
// r_p (perceptual roughness, GGX alpha = r_p^2) and, in 4D, theta_o. Each axis is linear in one
// quantity of the export vocabulary between min and max; texel i of N holds the value at
// i/(N-1) of the range (end values on texel centres). The 3D table has b = n, so theta_o = beta.
// Values are stored in logical order (A fastest, then beta, r_p, theta_o); `layout` permutes
// them into the file's x, y, z(, w) order.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace gtbake {
class Progress;
}

namespace gtbake::gtso {

struct Axis {
  std::string quantity;  // "A", "cos_alpha_v", "alpha_v", "cos_beta", "beta", "r_p", "alpha",
                         // "cos_theta_o", "theta_o"
  double min = 0.0, max = 1.0;
  double value(int i, int n) const { return min + (max - min) * i / (n - 1); }
};

// The physical parameters of one table entry.
struct GtsoPoint {
  double A, beta, r_p, thetaO;
};

struct Mapping {
  std::array<Axis, 4> axes;           // logical order: A, beta, roughness, theta_o (unused in 3D)
  static Mapping defaults(int dims);  // A, cos_beta, r_p, cos_theta_o
  // Axis swapped to its alternative quantity (logical axis index 0..3), same physical range.
  Mapping withAlternative(int axis) const;
  std::string name() const;  // e.g. "A,cos_beta,r_p,cos_theta_o"
};

// Axis quantity -> physical parameter and back.
double axisToPhysical(const std::string& quantity, double q);  // A, beta, r_p or theta_o
double physicalToAxis(const std::string& quantity, double p);

struct Table {
  int dims = 3, size = 32;
  Mapping mapping;
  std::vector<double> values;  // logical order, A fastest
  std::size_t index(const std::array<int, 4>& i) const;
  GtsoPoint point(const std::array<int, 4>& i) const;  // physical parameters of a texel
  // Multilinear interpolation at physical parameters (clamped to the axis ranges).
  double lookup(const GtsoPoint& p) const;
};

// Bakes S over every texel: one integrator line per (r_p, beta) in 3D, per (r_p, theta_o) in 4D
// (all beta and A of a line from one lobe); TBB-parallel over lines, deterministic.
Table bakeTable(int dims, const Mapping& mapping, int size, int cells, Progress* progress);

// Direct evaluation of S at physical parameters (3D: thetaO is ignored and taken = beta).
double evaluateS(int dims, const GtsoPoint& p, int cells);

struct ErrorStats {
  double max = 0.0, rms = 0.0;
};

// Interpolation error |lookup - direct| at `count` seeded random points, uniform in
// (A, cos beta, r_p, cos theta_o) over the table's physical ranges (r_p in [rpMin, 1]).
ErrorStats interpolationError(const Table& table, int count, int cells, std::uint64_t seed,
                              double rpMin = 0.0);

// Values of the table in file order: file axis d (x, y, z, w) is logical axis layout[d].
std::vector<float> toLayout(const Table& table, const std::array<int, 4>& layout);

// BC4-like proxy: per 4x4 block over x, y: 8-bit endpoints at the block's floor(min) / ceil(max),
// 8-level palette between them, nearest index. Returns the error of the decoded values.
ErrorStats bc4ProxyError(const std::vector<float>& fileOrder, int dims, int size);

}  // namespace gtbake::gtso
