// The path-traced points a fit reads: every unmasked pixel of every scene of a `gtbake sweep`.
//
// A sweep directory holds sweep.json and one EXR per scene with channels A, P1..PK, G010..G090,
// mask and the two half-sample estimates H0.A, H0.P1.., H1.A, H1.P1.. (even / odd samples; the
// full estimate is their mean). docs/sweep.md §1: A = p_0 and G(ρ) = Σ_{k=0..K} ρ^k p_k.
// loadSweep() validates everything it reads and throws a one-line gtbake::Error on bad input.
#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace gtbake {

// Fewer unmasked points than this cannot support the fit (points; 3 coefficients per albedo and a
// variance estimate from half-sample differences need thousands to be meaningful).
inline constexpr std::size_t kMinFitPoints = 1000;
// A scene must contribute at least this many unmasked points (points; its error row needs them).
inline constexpr std::size_t kMinScenePoints = 16;

// Pooled samples of one estimate (the full one or one half): A_i and G_i(ρ_j) for every point.
struct PointSet {
  std::vector<double> A;               // [point]
  std::vector<std::vector<double>> G;  // [albedo][point]
};

struct SweepScene {
  std::string name;       // the view (one image)
  std::size_t begin = 0;  // first point of this scene in the pooled arrays
  std::size_t end = 0;    // one past its last point
  // Its scene (sweep.json "scene": the views of one scene share it, one cluster of the scene-level
  // uncertainty, docs/fit.md §5) and scene type (sweep.json "type"); empty: the name, as in sweeps
  // before views (each image was its own scene).
  std::string cluster{};
  std::string type{};
};

struct SweepData {
  std::filesystem::path dir;
  int spp = 0;
  int bounces = 0;
  std::vector<double> albedos;  // ρ_j, as listed in sweep.json
  std::vector<SweepScene> scenes;
  PointSet full;     // the stored channels A and G###
  PointSet half[2];  // H0.* and H1.*, G recomputed as Σ ρ^k P_k with P_0 = A
  std::size_t points() const { return full.A.size(); }
};

// The EXR channel holding G at albedo ρ: "G" followed by round(100 ρ) in three digits (G010).
std::string albedoChannel(double rho);

// Reads and validates a sweep directory. With a radius R, the near-field truth at that G-buffer
// radius (docs/sweep.md, "Near-field truth") in place of the unbounded one: A_R, P1_R.., G###_R
// and their halves; a radius the sweep did not trace (sweep.json settings "gbuffer_radii") is a
// one-line gtbake::Error naming the radii it holds.
SweepData loadSweep(const std::filesystem::path& dir, std::optional<double> radius = std::nullopt);

// Sweeps of one directory already in memory, by the truth radius each was read at (none: the
// unbounded truth). Fits that run side by side on the same sweep (gtbake all's profiles) share
// them instead of each decoding every image again.
using LoadedSweeps = std::map<std::optional<double>, SweepData>;

// A copy of `loaded`'s sweep at `radius` when it holds one (it must have been read from `dir`),
// else loadSweep(dir, radius).
SweepData loadSweep(const std::filesystem::path& dir, std::optional<double> radius,
                    const LoadedSweeps* loaded);

}  // namespace gtbake
