// The reader of a `gtbake screen-ao` output set (docs/screen_ao.md §6), owned by the stage that
// writes it: screen_ao.json's images and estimators with their settings' radii, and each image's
// Â, mask and b̂ per estimator, every file verified against the set's manifest. Every problem is
// one gtbake::Error line. No estimator code: what fit, tune and validate-gtso link.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/output_set.h"

namespace gtbake {

// A bent normal further than this from unit length is not one (screen-ao stores normalised
// vectors; RGBA8 decoding and float rounding stay far below it). Both readers of b̂ use it: this
// set's and an imported pass's (screen_ao_import.h).
inline constexpr double kBentUnitTolerance = 1e-3;

// "(x, y)" of pixel p in an image `width` pixels wide, for a reader's error.
std::string pixelText(std::size_t p, int width);

// Float rounding of an estimator's slice integrals may leave Â a few ulps outside [0, 1]
// (1.00000012 on an open pixel); such values are clamped, anything farther is an error.
inline constexpr float kEstimateRounding = 1e-5f;
// Â clamped to [0, 1] when within that rounding of it; nullopt when farther (the caller names it).
std::optional<float> clampedEstimate(float a);

// Which A a fit reads: the sweep's ray-traced A (estimator empty) or a screen-space estimate.
struct AoInput {
  std::string estimator;            // "" = ray-traced; else a `gtbake screen-ao` estimator name
  std::filesystem::path screen_ao;  // its output directory (the set screen_ao.manifest.json)
  // Score against the unbounded truth (A, G, S) instead of the near-field truth at the
  // estimator's own radius (`--truth unbounded`; docs/sweep.md, "Near-field truth").
  bool unbounded_truth = false;
  bool rayTraced() const { return estimator.empty(); }
};

// One image of a screen-ao set at every pixel (row-major): the mask (1 = geometry), the
// estimator's Â (clamped to [0, 1] where float rounding left it just outside) and, when read, its
// bent normal b̂ (world space, 3 per pixel, as screen-ao stored it).
struct ImageEstimate {
  std::string file;  // where it was read, for messages
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> mask;
  std::vector<float> A;
  std::vector<float> bent;  // empty unless read with bent normals
};

// A `gtbake screen-ao` set opened for one estimator: its manifest and images, every file
// verified against the manifest when read. Opening throws a one-line gtbake::Error when the set
// is not a screen-ao result or does not hold the estimator.
class ScreenEstimateSet {
 public:
  explicit ScreenEstimateSet(const AoInput& input);
  // The image the sweep calls `name` (`sweep` only names it in the message when it is missing).
  // Throws when the set lacks it, when Â is outside [0, 1] by more than float rounding (1e-5) or
  // b̂ is not a finite unit vector (within 1e-3) at an unmasked pixel.
  ImageEstimate read(const std::string& name, const std::filesystem::path& sweep,
                     bool with_bent) const;
  // The radius screen-ao ran the estimator at (screen_ao.json settings.<estimator>.radius), the
  // radius of its near-field truth; a set without a positive one is a one-line gtbake::Error.
  double radius() const;

 private:
  AoInput input_;
  std::optional<double> radius_;
  OutputManifest manifest_;
  std::map<std::string, std::string> files_;  // image name -> EXR file name
};

// The G-buffer radius whose near-field truth scores `input`: the radius screen-ao used for the
// estimator (ScreenEstimateSet::radius); none for ray-traced input or --truth unbounded.
std::optional<double> truthRadius(const AoInput& input);

}  // namespace gtbake
