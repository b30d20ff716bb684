// readGltfScene with options: which camera, whether external files may lie outside the glTF's
// directory. The rules (docs/limits.md): every buffer and image uri is resolved against the
// directory of the .gltf/.glb itself, never the current directory; absolute uris and ".."
// components (also percent-encoded, "%2e%2e") are refused unless allow_outside is set; only
// regular files are opened (a FIFO would block); instances, vertices, triangles, JSON nesting and
// file sizes are bounded (input_limits.h) and the error names the limit and its variable.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace gtbake {

struct GltfReadOptions {
  // Camera to use: "" = the first perspective camera met in the depth-first walk; otherwise a
  // camera or camera-node name, or the index of the camera instance in walk order ("0", "1"...).
  std::string camera;
  // Allow buffer/image uris outside the glTF's directory (absolute or with "..").
  bool allow_outside = false;
  // A scene without a perspective camera is returned with the default camera (the caller places
  // automatic views, auto_camera.h) instead of refused; `info` then counts 0 cameras.
  bool allow_no_camera = false;
};

struct GltfReadInfo {
  int perspective_cameras = 0;  // perspective camera instances met in the walk
  int camera_instance = -1;     // index (walk order) of the one used
  std::string camera_name;      // its camera name, or its node name if the camera has none
  // The orthographic camera instances met in the walk, never used (gtbake traces perspective
  // views only): camera name, else node name, else "camera <index>".
  std::vector<std::string> orthographic_cameras;
  // SHA-256 of the bytes the scene was read from: the glTF and every external buffer the loader
  // opened (gltf_loading.h); a sweep's identity key includes it (docs/limits.md §Paths).
  std::string input_sha256;
};

Scene readGltfScene(const std::filesystem::path& path, const GltfReadOptions& options,
                    GltfReadInfo* info = nullptr);

}  // namespace gtbake
