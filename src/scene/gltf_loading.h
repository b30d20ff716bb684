// The tinygltf model of a .gltf/.glb read under readGltfScene's rules (gltf_reader.h): a regular
// file, JSON nesting bounded, buffer and image uris only beside the file (unless allow_outside),
// never the current directory, images never decoded, required extensions refused unless they
// cannot change geometry (checked on the JSON first, so a Draco file names its extension rather
// than failing on its accessors). Throws gtbake::Error with a one-line reason prefixed by the path.
#pragma once

#include <tiny_gltf.h>

#include <filesystem>

namespace gtbake {

tinygltf::Model loadGltfModel(const std::filesystem::path& path, bool allow_outside);

}  // namespace gtbake
