// `gtbake screen-ao --import NAME=DIR[:radius=R]`: an engine's own screen-space pass, run on the
// G-buffer `gtbake gbuffer` exported, added to the screen-ao set as estimator NAME
// (docs/screen_ao.md §8, "Bring your own pass").
#pragma once

#include <filesystem>
#include <string>

#include "screen_ao/estimate.h"
#include "screen_ao/gbuffer.h"

namespace gtbake {

struct ImportedEstimator {
  std::string name;
  std::filesystem::path dir;  // one <image>.exr per swept image
  double radius = 0.0;        // metres, scored against the sweep's A_R of it; 0 = none given
};

// An imported estimator's name: 1 to 64 of [a-z0-9_-], starting with a letter or digit, not
// "all" or "none" and not a built-in's name (it names EXR channels, PNGs and the profile's
// directory). Throws a one-line gtbake::Error naming `option`.
void checkImportedName(const std::string& name, const std::string& option);
// Whether `name` may name a screen-ao estimator: a built-in or a valid imported name.
bool isEstimatorName(const std::string& name);

// "NAME=DIR" or "NAME=DIR:radius=R" (R positive, finite metres). Throws a one-line gtbake::Error.
ImportedEstimator parseImport(const std::string& text);

// Throws unless every image of the sweep holds the A_R channel of e.radius (when given).
void checkImportRadius(const ImportedEstimator& e, const std::vector<SweepImage>& images);

// Decodes the user's EXR of `image` (bytes read from `file`, for messages): channel A, and the
// bent normal as BNX BNY BNZ (world space) or VBNX VBNY VBNZ (view space), at most one of the two;
// without either b̂ is the G-buffer's normal. At unmasked pixels A must be finite in [0, 1] and b̂ a
// finite unit vector (within 1e-3, used as given); masked pixels are ignored and stored as 0, as
// the built-in estimators store them. Throws a one-line gtbake::Error.
AoEstimate decodeImportedEstimate(const std::string& bytes, const std::string& file,
                                  const SweepImage& image);
// Reads <dir>/<fileSlug(image.name)>.exr (a regular file, at most the EXR size limit) and decodes
// it; a missing file is a one-line gtbake::Error.
AoEstimate readImportedEstimate(const ImportedEstimator& e, const SweepImage& image);

}  // namespace gtbake
