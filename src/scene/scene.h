// A scene as the sweep sees it: world-space triangles and one perspective camera.
//
// Conventions (glTF 2.0): right-handed, metres, +Y up in the generated scenes. The camera looks
// along its local −Z with +Y up; `basis` holds its local axes in world space as columns
// (right, up, backward). Pixel (i, j) of a W×H image, j = 0 the top row, is the ray through
// ((i + 0.5)/W, (j + 0.5)/H) of the image plane. Surfaces are two-sided.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace gtbake {

struct PerspectiveCamera {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Matrix3d basis = Eigen::Matrix3d::Identity();  // columns: right, up, backward
  double yfov = 0.8;                                    // vertical field of view, radians
};

struct Scene {
  std::string name;
  // The scene type (glTF scene extras "gtbake_type": the generated scenes carry it); "" when the
  // file names none.
  std::string type;
  std::vector<Eigen::Vector3f> positions;               // world space
  std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise seen from the front
  PerspectiveCamera camera;
};

// Reads a glTF 2.0 file (.gltf + .bin, or .glb): every mesh primitive of mode TRIANGLES under the
// default scene's node hierarchy, transformed to world space, and the first perspective camera
// found. Throws gtbake::Error with a one-line reason for anything unsupported.
Scene readGltfScene(const std::filesystem::path& path);

// The bytes of `scene` written as <stem>.gltf: the JSON text (its buffer uri is <stem>.bin) and
// the buffer.
struct GltfFiles {
  std::string gltf;
  std::string bin;
};
GltfFiles encodeGltfScene(const std::string& stem, const Scene& scene);

// Writes `scene` as <path> (.gltf, JSON) plus <path minus extension>.bin, atomically.
void writeGltfScene(const std::filesystem::path& path, const Scene& scene);

}  // namespace gtbake
