// The per-pixel inputs of validate-gtso from a `gtbake sweep` directory: every unmasked pixel's
// A, normal n, view direction ωo, bent normal b and path-traced S (with its half-sample
// estimates) at each roughness of the sweep (docs/sweep.md §1; docs/sweep.md §4).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "screen_ao/screen_ao_set.h"

namespace gtbake {

struct SpecularScene {
  std::string name;
  // The scene this entry views (sweep.json views[].scene; empty: its own name): views of one
  // scene are one unit of every scene-level statistic (docs/validate_gtso.md §3).
  std::string cluster;
  std::string type;  // sweep.json "type" (else the cluster): the delete-one-type jackknife's unit
  // The unit names with their fallbacks (sweeps before views: each image its own scene, its scene
  // its type).
  const std::string& sceneName() const { return cluster.empty() ? name : cluster; }
  const std::string& typeName() const { return type.empty() ? sceneName() : type; }
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> mask;  // per pixel, 1 = geometry
  std::vector<float> A;            // per pixel
  std::vector<float> normal;       // 3 per pixel (NX NY NZ)
  std::vector<float> view;         // 3 per pixel (VX VY VZ)
  std::vector<float> bent;         // 3 per pixel (BNX BNY BNZ)
  // [roughness][pixel]: Ŝ and its half-sample estimates H0, H1.
  std::vector<std::vector<float>> S;
  std::vector<std::vector<float>> H0;
  std::vector<std::vector<float>> H1;
};

struct SpecularSweep {
  std::filesystem::path dir;
  int spp = 0;
  int specular_spp = 0;
  std::vector<double> roughness;  // r_p of each S channel, as sweep.json lists them
  // The G-buffer radius of the near-field S_R read (docs/sweep.md, "Near-field truth"); none:
  // the unbounded S.
  std::optional<double> radius;
  std::vector<SpecularScene> scenes;
};

// Reads sweep.json and every scene's EXR. A sweep traced without specular channels (or an EXR
// missing one of them) is a one-line gtbake::Error naming --specular-roughness. With a radius,
// S_R and its halves (S010_R1 …) in place of S; a radius the sweep lacks is a one-line error.
SpecularSweep readSpecularSweep(const std::filesystem::path& dir,
                                std::optional<double> radius = std::nullopt);

// What the runtime feeds its specular occlusion (docs/validate_gtso.md §6): every scene's A and
// bent normal replaced by a screen-space estimator's Â and b̂ (input.estimator of the screen-ao
// set input.screen_ao). The set's images must be the sweep's: an image missing or a mask that
// differs from the sweep's is a one-line gtbake::Error (ScreenEstimateSet checks the values).
void useScreenEstimate(SpecularSweep* sweep, const AoInput& input);

}  // namespace gtbake
