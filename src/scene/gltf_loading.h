// The tinygltf model of a .gltf/.glb read under readGltfScene's rules (gltf_reader.h): a regular
// file, JSON nesting bounded, buffer and image uris only beside the file (unless allow_outside),
// never the current directory, images never decoded, required extensions refused unless they
// cannot change geometry (checked on the JSON first, so a Draco file names its extension rather
// than failing on its accessors). Throws gtbake::Error with a one-line reason prefixed by the path.
// Images are never opened. `input_sha256` (if given) receives the hash of every byte the model was
// read from: SHA-256 of one line "<name> <size> <sha256>" for the glTF file and then for each
// external buffer in the order tinygltf read it (docs/limits.md §Paths).
#pragma once

#include <tiny_gltf.h>

#include <filesystem>
#include <string>

namespace gtbake {

tinygltf::Model loadGltfModel(const std::filesystem::path& path, bool allow_outside,
                              std::string* input_sha256 = nullptr);

}  // namespace gtbake
