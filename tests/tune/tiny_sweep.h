// A small sweep with G-buffer channels for the tune tests: classic scenes of data/scenes traced at
// 48 × 48 px with 16 walks, one view each, as tests/screen_ao's command fixture traces its scene.
// Fewer pixels or two views of each scene at this size leave Â ≈ 1 nearly everywhere outside
// `corner`, and the profile refit without `corner` is then not determined.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace gtbake::test {

// Sweeps `scenes` (stems of data/scenes/*.gltf) into `out` and returns it.
std::filesystem::path tinySweep(const std::filesystem::path& out,
                                const std::vector<std::string>& scenes);

}  // namespace gtbake::test
