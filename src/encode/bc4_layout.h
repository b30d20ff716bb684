// The texture layout of each GTSO volume, chosen by `gtbake export` with the real BC4 encoder
// (docs/export.md §2a).
//
// A layout (runtime/gtso_runtime.h GtsoLayout) assigns the table axes (A, theta_o or beta, r_p) to
// texture x, y, z; the BC4 blocks are 4x4 over (x, y) and the 4D theta_o axis always folds into
// the depth. Each candidate is encoded with the exact encoder and scored end to end as the runtime
// reads it: BC4 decode, half-texel remap, trilinear filter and 4D fold through the shipped lookup
// code, against the exact S (gtso::makeErrorPoints at the bake's integrator resolution) on a
// seeded uniform point set independent of the bake and of gtso's report seeds, and reported on a
// fresh seed. Rule: the lowest uniform RMS; candidates within kLayoutRmsTie of it tie, and the tie
// goes to the lowest uniform max, then to the earlier candidate (identity first). All texel formats
// of a table (BC4, R16, R8) are written in the chosen layout, so one lookup reads them all.
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "gtso/gtso_set.h"
#include "gtso/gtso_tables.h"
#include "runtime/gtso_runtime.h"
#include "texture/bc4_encoder.h"

namespace gtbake {

inline constexpr double kLayoutRmsTie = 0.01;       // relative RMS difference counted as a tie
inline constexpr std::uint64_t kLayoutSeed = 1001;  // gtso: axes chosen on 1-3, reports 10-12
inline constexpr std::uint64_t kLayoutReportSeed = 1002;  // fresh points the choice is reported on
inline constexpr int kLayoutLobes = 512;  // uniform lobes x 16 points (stress: a quarter)

struct LayoutOptions {
  int lobes = kLayoutLobes;
  std::uint64_t seed = kLayoutSeed;               // the points the choice is made on
  std::uint64_t report_seed = kLayoutReportSeed;  // fresh points every candidate is reported on
  int cells = 0;                       // integrator cells of the exact S; 0 = gtso.json's (or 96)
  const GtsoLayout* forced = nullptr;  // tests: skip the choice, use this layout
  // Progress bars (exact S at the points per lobe, then the candidates' blocks) under this
  // label; nullptr: silent.
  const char* progress_label = nullptr;
};

struct LayoutCandidate {
  GtsoLayout layout{};
  double uniform_rms = 0.0, uniform_max = 0.0, stress_rms = 0.0, stress_max = 0.0;
  // The same on the fresh report seed (not used by the choice).
  double report_uniform_rms = 0.0, report_uniform_max = 0.0;
  double report_stress_rms = 0.0, report_stress_max = 0.0;
  double texel_rms = 0.0, texel_max = 0.0;  // decoded texels vs the float table
  double encode_seconds = 0.0;
};

struct LayoutChoice {
  GtsoLayout layout = kGtsoIdentityLayout;
  std::array<int, 3> volume{};  // texture extent in that layout (4D: depth folds theta_o)
  std::vector<float> texels;    // the float table in texture order of that layout
  Bc4Volume bc4;                // its BC4 encoding
  std::vector<LayoutCandidate> candidates;
  int chosen = 0;
  nlohmann::json json;  // candidates, rule, points and choice for export.json
  // The fresh report points (seed options.report_seed) with their exact S, the lobes they were
  // drawn with and the integrator cells: the texel formats are measured on them too
  // (format_errors.h).
  gtso::ErrorPoints report_uniform, report_stress;
  int lobes = 0, stress_lobes = 0, exact_cells = 0;
};

// |runtime lookup of volume v (any texel format) in `layout` − exact S| over the points: max,
// RMS and the worst point.
gtso::ErrorStats layoutLookupError(const GtsoTable& t, const GtsoVolume& v,
                                   const GtsoLayout& layout, const gtso::ErrorPoints& pts);

// The candidates of a table: 3D every permutation of (A, theta_o, r_p); 4D the three block planes
// of (A, beta, r_p) (x before y: swapping x and y keeps every block's 16 texels, so the exact
// encoder gives the same decoded texels up to its summation order; measured identical on 3D).
// Only layouts whose x and y extents are multiples of 4 (BC4 blocks).
std::vector<GtsoLayout> layoutCandidates(const GtsoTable& t);
// Texture extent and texel order of a table in a layout (4D: its theta_o tiles, GtsoLayout;
// texels of tiles past the last slice are 0).
std::array<int, 3> layoutVolume(const GtsoTable& t, const GtsoLayout& layout);
std::vector<float> permuteToLayout(const GtsoTable& t, const GtsoLayout& layout);

// How the 4D table's theta_o slices are packed (docs/export.md §2c): `atlas` tiles them across
// texture x and down z within kAtlasMaxExtent texels per dimension (the guaranteed 3D limit of
// Vulkan and OpenGL ES 3); `fold` stacks them down z (one column of tiles, depth N_z N_w).
enum class Layout4D { kAtlas, kFold };
inline constexpr int kAtlasMaxExtent = 256;
// "atlas" / "fold" and back (throws gtbake::Error on another name).
const char* layout4DName(Layout4D packing);
Layout4D parseLayout4D(const std::string& name);
// The tiles across x of table `t` in `layout` packed as `packing`: fold 1; atlas the fewest
// columns that keep the depth within max_extent (at most floor(max_extent / N_z) tiles down z),
// with every extent within max_extent, else a one-line gtbake::Error naming the table.
int tilesAcrossX(const GtsoTable& t, const GtsoLayout& layout, Layout4D packing, int max_extent);

// Texel (x, y, z) of slice w of a 4D table in layout order <-> texel of the tiled volume
// (GtsoLayout::tilesX; n = the tile's extents). tiledTexel is one to one; tableTexel of a texel
// in a tile past the last slice gives w >= nw.
std::array<int, 3> tiledTexel(const GtsoLayout& layout, const int* n, const std::array<int, 4>& i);
std::array<int, 4> tableTexel(const GtsoLayout& layout, const int* n, const std::array<int, 3>& v);

// Packs a 4D choice (made on the fold, tilesX = 1) as `packing` (tilesAcrossX): its texels and
// its BC4 blocks reordered (every block lies in one tile; blocks of tiles past the last slice are
// zero, the encoding of zero texels), errors unchanged; layouts/4d of encode.json gains
// `packing` and the new `volume`.
void packLayoutChoice(const GtsoTable& t, Layout4D packing, int max_extent, LayoutChoice* choice);
// "xyz"[axis[0]] "xyz"[axis[1]] "xyz"[axis[2]]: the shader swizzle of a layout, e.g. "yzx".
std::string layoutSwizzle(const GtsoLayout& layout);

LayoutChoice chooseLayout(const Bc4Encoder& encoder, const GtsoTable& t, const GtsoInput& gtso,
                          const LayoutOptions& options);

// Both tables' choices: what export writes, and what `gtbake all` hands to validate-gtso (which
// runs before export) so both read the same blocks without choosing twice.
struct GtsoLayouts {
  LayoutChoice t3, t4;
};
// forced3 / forced4: nullptr to choose.
GtsoLayouts chooseLayouts(const GtsoInput& gtso, int lobes, const GtsoLayout* forced3,
                          const GtsoLayout* forced4, bool progress);

}  // namespace gtbake
