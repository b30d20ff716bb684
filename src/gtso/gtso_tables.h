// The 3D and 4D GTSO tables: baking on the warped axes of runtime/gtso_runtime.h, the
// texel formats an engine reads (float32, BC4_UNORM, R16_UNORM, R8_UNORM), and the end-to-end
// error of what the runtime reads against direct integration at random and stress points.
//
// Axes and texel order (docs/gtso.md §1): x = A (step-warped), y = beta (3D: theta_o), z = r_p,
// w = theta_o (4D), x fastest; the 4D table is folded into a volume of depth N_z * N_w. The axis
// maps themselves live in gtso_runtime.h (one definition for bake, lookup and generated code).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "texture/texel_format.h"

namespace gtbake {
class Progress;
}

namespace gtbake::gtso {

// The physical parameters of one table entry (angles in radians).
struct GtsoPoint {
  double A, beta, r_p, theta_o;
};

// The quantity along a table axis (docs/gtso.md §1), named as gtso.json, encode.json and the
// generated code's layout comments spell it: "A", "theta_o", "beta", "r_p".
enum class TableAxis { kA, kThetaO, kBeta, kRoughness };
const char* axisName(TableAxis axis);
// The quantity along axis `axis` (0 = x, 1 = y, 2 = z, 3 = w) of the 3D table (A, theta_o, r_p)
// or the 4D table (A, beta, r_p, theta_o).
TableAxis tableAxis(int dims, int axis);

// One table axis as gtso.json names it: its quantity, the forward map a shader evaluates and its
// ALU cost (the code is gtso_runtime.h and its shader ports).
struct AxisDefinition {
  const char* quantity;
  const char* forward;
  const char* alu;
};
// The axes of the 3D (x, y, z) and 4D (x, y, z, w) tables.
const std::vector<AxisDefinition>& axisDefinitions(int dims);

struct Table {
  int dims = 3, size = 32;
  std::vector<double> values;  // x fastest
  std::size_t index(const std::array<int, 4>& i) const;
  GtsoPoint point(const std::array<int, 4>& i) const;  // physical parameters of a texel
  std::array<int, 3> volume() const;                   // texture extent (4D folded)
};

// Bakes S over every texel: one integrator lobe per (r_p, theta_o) line (3D: b = n; 4D: every
// beta of the line from the same lobe, each bent normal with its own warped A cones);
// TBB-parallel over lines, deterministic. size in [4, 256], a multiple of 4 (BC4 blocks).
// `lines` (optional): bake only these lines, line = r_p texel * size + theta_o texel; the other
// texels stay 0 (the sampled texel check of texel_check.h).
Table bakeTable(int dims, int size, int cells, Progress* progress,
                const std::vector<std::size_t>* lines = nullptr);
void validateTableSize(int size);  // throws gtbake::Error with a one-line reason

// Direct evaluation of S at physical parameters (3D: theta_o is ignored and taken = beta).
double evaluateS(int dims, const GtsoPoint& p, int cells);

// ---- texel formats ----

// A table as one texture format: raw texel bytes in texture memory order (BC4: blocks). gtso
// makes only the float32 one (floatTable); `gtbake encode` makes the others (docs/export.md §2).
struct EncodedTable {
  TexelFormat format = TexelFormat::kFloat32;
  std::vector<std::uint8_t> bytes;
  double texel_max = 0.0, texel_rms = 0.0;  // decoded texels vs the float64 table
};
// The table's float32 texels, texture order (texel_max, texel_rms: its float rounding).
EncodedTable floatTable(const Table& t);
// The runtime lookup (gtso_runtime.h) on a table in any texel format, texture order (identity
// layout), at physical parameters.
float runtimeLookup(const Table& t, const EncodedTable& e, const GtsoPoint& p);

// ---- end-to-end error ----
struct ErrorStats {
  double max = 0.0, rms = 0.0;
  GtsoPoint worst{};
};
enum class PointSet { kUniform, kStress };
const char* pointSetName(PointSet s);
// Random points grouped by lobe: `lobes` random (r_p, theta_o), `perLobe` random points each
// (4D: 4 random beta with perLobe/4 random A each; 3D: perLobe random A),
// with their exact S (integrator at `cells`), deterministic in seed.
// Uniform: A, r_p, cos theta_o uniform in [0, 1]; 3D beta = theta_o; 4D cos beta uniform over the
// bent normals above the horizon, beta in [0, theta_o + pi/2]. Stress: half the lobes at grazing
// views (cos theta_o in [0, 0.1]; half of those with cos theta_o = 0.1 v² and r_p = v'², v, v'
// uniform, towards the grazing mirror-like corner where the largest errors are), and every point
// within 3 lobe widths of the mirror step: alpha_v uniform in [s - h, s + h] intersected with [0,
// pi/2], h = 6 alpha + 0.02 rad (3 widths of ~2 alpha plus a floor), s = beta (3D: theta_o); 4D
// stress beta in [0, pi/2] (cos beta uniform).
inline constexpr int kPointsPerLobe = 16;  // points per random lobe of every end-to-end set
struct ErrorPoints {
  std::vector<GtsoPoint> points;
  std::vector<double> exact;
};
// lobes x perLobe points and exact values, zero until a point set fills them lobe by lobe.
ErrorPoints sizedErrorPoints(int lobes, int perLobe);
// `progress` (optional) advances by one per lobe.
ErrorPoints makeErrorPoints(int dims, PointSet set, int lobes, int perLobe, std::uint64_t seed,
                            int cells, Progress* progress = nullptr);
// The 3D and 4D sets of one seed drawn on the same random lobes (the 4D stream's lobes; the 3D
// points from the 3D stream), each lobe integrated once for both: the end-to-end measurement of
// `gtbake gtso` at about the cost of the 4D set alone.
struct ErrorPointPair {
  ErrorPoints three, four;
};
ErrorPointPair makeErrorPointPair(PointSet set, int lobes, int perLobe, std::uint64_t seed,
                                  int cells);
ErrorStats lookupError(const Table& t, const EncodedTable& e, const ErrorPoints& pts);
// Max, RMS and the worst point of the errors err[i] at pts.points[i].
ErrorStats errorStats(const std::vector<double>& err, const ErrorPoints& pts);

// Values of the table as float32, texture order.
std::vector<float> toFloats(const Table& t);

// A = sin^2 alpha_v with alpha_v at fraction v of the part of [centre - half, centre + half]
// inside [0, pi/2]: the point sets' draw near the mirror step (no mass piled up at the ends by
// clamping).
double stepWindowA(double centre, double half, double v);

}  // namespace gtbake::gtso
