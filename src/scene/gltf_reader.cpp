// readGltfScene: glTF 2.0 (.gltf + buffers, or .glb) to world-space triangles and one camera.
//
// Supported: the default scene (scene 0 if none is marked), the full node hierarchy (matrix or
// translation/rotation/scale, composed parent × child), meshes whose primitives are TRIANGLES
// with float VEC3 POSITION (any byteStride and accessor offset), with or without u8/u16/u32
// indices, and the first perspective camera met in a depth-first walk of that scene, placed by
// its node's world transform (scale removed). Nodes whose world transform mirrors (negative
// determinant) have their winding flipped so triangles stay counter-clockwise from the front
// (glTF 2.0 §3.7.4). Skins, morph targets, materials and images are ignored.
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <set>

#include "common/error.h"
#include "scene/scene.h"

namespace gtbake {
namespace {

// Required extensions that cannot change the geometry or the camera, so are safe to ignore.
bool ignorableExtension(const std::string& name) {
  return name.rfind("KHR_materials_", 0) == 0 || name == "KHR_texture_transform" ||
         name == "KHR_lights_punctual" || name == "KHR_texture_basisu";
}

std::string oneLine(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

const char* modeName(int mode) {
  switch (mode) {
    case TINYGLTF_MODE_POINTS:
      return "POINTS";
    case TINYGLTF_MODE_LINE:
      return "LINES";
    case TINYGLTF_MODE_LINE_LOOP:
      return "LINE_LOOP";
    case TINYGLTF_MODE_LINE_STRIP:
      return "LINE_STRIP";
    case TINYGLTF_MODE_TRIANGLE_STRIP:
      return "TRIANGLE_STRIP";
    case TINYGLTF_MODE_TRIANGLE_FAN:
      return "TRIANGLE_FAN";
    default:
      return "unknown";
  }
}

Eigen::Matrix4d localTransform(const tinygltf::Node& node) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (node.matrix.size() == 16) {
    for (int k = 0; k < 16; ++k) m(k % 4, k / 4) = node.matrix[k];  // column-major
    return m;
  }
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (node.translation.size() == 3) {
    t.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
  }
  if (node.rotation.size() == 4) {
    t.rotate(
        Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2])
            .normalized());
  }
  if (node.scale.size() == 3) t.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
  return t.matrix();
}

class Reader {
 public:
  Reader(const tinygltf::Model& model, Scene* scene) : model_(model), scene_(scene) {}

  void walk(int node_index, const std::optional<Eigen::Matrix4d>& parent, int depth) {
    if (node_index < 0 || node_index >= static_cast<int>(model_.nodes.size())) {
      throw Error("node index " + std::to_string(node_index) + " is out of range");
    }
    if (depth > static_cast<int>(model_.nodes.size())) {
      throw Error("the node hierarchy has a cycle (through node " + std::to_string(node_index) +
                  ")");
    }
    const tinygltf::Node& node = model_.nodes[node_index];
    const Eigen::Matrix4d local = localTransform(node);
    const Eigen::Matrix4d world = parent ? Eigen::Matrix4d(*parent * local) : local;
    if (!world.allFinite()) {
      throw Error("node " + std::to_string(node_index) + " has a non-finite transform");
    }
    if (node.mesh >= 0) addMesh(node.mesh, world);
    if (node.camera >= 0) addCamera(node.camera, world);
    for (int child : node.children) walk(child, world, depth + 1);
  }

  bool sawOrthographic() const { return saw_orthographic_; }
  bool hasCamera() const { return has_camera_; }

 private:
  // Byte address of element `i` of an accessor after checking it lies inside its buffer.
  const unsigned char* element(const tinygltf::Accessor& accessor, std::size_t element_size,
                               const std::string& what) const {
    if (accessor.sparse.isSparse) throw Error(what + " uses a sparse accessor (unsupported)");
    if (accessor.bufferView < 0 ||
        accessor.bufferView >= static_cast<int>(model_.bufferViews.size())) {
      throw Error(what + " has no buffer view");
    }
    const tinygltf::BufferView& view = model_.bufferViews[accessor.bufferView];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model_.buffers.size())) {
      throw Error(what + " refers to a missing buffer");
    }
    const tinygltf::Buffer& buffer = model_.buffers[view.buffer];
    const std::size_t stride = view.byteStride ? view.byteStride : element_size;
    const std::size_t begin = view.byteOffset + accessor.byteOffset;
    const std::size_t end =
        accessor.count == 0 ? begin : begin + (accessor.count - 1) * stride + element_size;
    if (stride < element_size || end > view.byteOffset + view.byteLength ||
        view.byteOffset + view.byteLength > buffer.data.size()) {
      throw Error(what + " reads past the end of its buffer view or buffer");
    }
    return buffer.data.data() + begin;
  }

  void addMesh(int mesh_index, const Eigen::Matrix4d& world) {
    if (mesh_index >= static_cast<int>(model_.meshes.size())) {
      throw Error("mesh index " + std::to_string(mesh_index) + " is out of range");
    }
    const tinygltf::Mesh& mesh = model_.meshes[mesh_index];
    const bool mirrored = world.topLeftCorner<3, 3>().determinant() < 0.0;
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const tinygltf::Primitive& prim = mesh.primitives[p];
      const std::string what = "mesh " + std::to_string(mesh_index) + " ('" + mesh.name +
                               "') primitive " + std::to_string(p);
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) {
        throw Error(what + " has mode " + modeName(prim.mode) +
                    "; only TRIANGLES primitives are supported");
      }
      const auto position = prim.attributes.find("POSITION");
      if (position == prim.attributes.end() || position->second < 0 ||
          position->second >= static_cast<int>(model_.accessors.size())) {
        throw Error(what + " has no POSITION attribute");
      }
      const tinygltf::Accessor& pos = model_.accessors[position->second];
      if (pos.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || pos.type != TINYGLTF_TYPE_VEC3) {
        throw Error(what + " POSITION is not float VEC3 (quantized positions are unsupported)");
      }
      const unsigned char* pos_data = element(pos, 12, what + " POSITION");
      const std::size_t pos_stride = [&] {
        const auto& view = model_.bufferViews[pos.bufferView];
        return view.byteStride ? view.byteStride : std::size_t{12};
      }();
      const auto base = static_cast<std::uint32_t>(scene_->positions.size());
      for (std::size_t i = 0; i < pos.count; ++i) {
        float xyz[3];
        std::memcpy(xyz, pos_data + i * pos_stride, sizeof(xyz));
        const Eigen::Vector4d p = world * Eigen::Vector4d(xyz[0], xyz[1], xyz[2], 1.0);
        const Eigen::Vector3f q = p.head<3>().cast<float>();
        if (!q.allFinite()) throw Error(what + " has a non-finite vertex position");
        scene_->positions.push_back(q);
      }
      std::vector<std::uint32_t> indices;
      if (prim.indices >= 0) {
        if (prim.indices >= static_cast<int>(model_.accessors.size())) {
          throw Error(what + " indices accessor is out of range");
        }
        const tinygltf::Accessor& acc = model_.accessors[prim.indices];
        const int size = acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                         : acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                         : acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                                       : 0;
        if (size == 0 || acc.type != TINYGLTF_TYPE_SCALAR) {
          throw Error(what + " indices are not unsigned 8-, 16- or 32-bit scalars");
        }
        const unsigned char* data = element(acc, size, what + " indices");
        const auto& view = model_.bufferViews[acc.bufferView];
        const std::size_t stride = view.byteStride ? view.byteStride : size;
        for (std::size_t i = 0; i < acc.count; ++i) {
          std::uint32_t v = 0;
          if (size == 1) v = data[i * stride];
          if (size == 2) {
            std::uint16_t s;
            std::memcpy(&s, data + i * stride, 2);
            v = s;
          }
          if (size == 4) std::memcpy(&v, data + i * stride, 4);
          if (v >= pos.count) {
            throw Error(what + " has index " + std::to_string(v) + " but only " +
                        std::to_string(pos.count) + " vertices");
          }
          indices.push_back(v);
        }
      } else {
        for (std::size_t i = 0; i < pos.count; ++i)
          indices.push_back(static_cast<std::uint32_t>(i));
      }
      if (indices.size() % 3 != 0) {
        throw Error(what + " has " + std::to_string(indices.size()) +
                    " indices, not a multiple of 3");
      }
      for (std::size_t t = 0; t < indices.size(); t += 3) {
        std::array<std::uint32_t, 3> tri = {base + indices[t], base + indices[t + 1],
                                            base + indices[t + 2]};
        if (mirrored) std::swap(tri[1], tri[2]);
        scene_->triangles.push_back(tri);
      }
    }
  }

  void addCamera(int camera_index, const Eigen::Matrix4d& world) {
    if (camera_index >= static_cast<int>(model_.cameras.size())) {
      throw Error("camera index " + std::to_string(camera_index) + " is out of range");
    }
    const tinygltf::Camera& camera = model_.cameras[camera_index];
    if (camera.type != "perspective") {
      saw_orthographic_ = true;
      return;
    }
    if (has_camera_) return;
    if (!(camera.perspective.yfov > 0.0 && camera.perspective.yfov < 3.14159)) {
      throw Error("camera " + std::to_string(camera_index) + " has an invalid yfov");
    }
    // Columns of the world matrix, scale removed; left bit-exact when already orthonormal so a
    // written camera reads back identical.
    Eigen::Matrix3d basis = world.topLeftCorner<3, 3>();
    const double kTolerance = 1e-12;
    if (!(basis.transpose() * basis).isIdentity(kTolerance)) {
      basis.col(0).normalize();
      basis.col(1) -= basis.col(0).dot(basis.col(1)) * basis.col(0);
      basis.col(1).normalize();
      basis.col(2) = basis.col(0).cross(basis.col(1));
      if (!basis.allFinite()) {
        throw Error("camera " + std::to_string(camera_index) + " has a degenerate transform");
      }
    }
    scene_->camera.position = world.block<3, 1>(0, 3);
    scene_->camera.basis = basis;
    scene_->camera.yfov = camera.perspective.yfov;
    has_camera_ = true;
  }

  const tinygltf::Model& model_;
  Scene* scene_;
  bool has_camera_ = false;
  bool saw_orthographic_ = false;
};

bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
  return true;  // images never matter to occlusion
}

}  // namespace

Scene readGltfScene(const std::filesystem::path& path) {
  const std::string where = path.string() + ": ";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw Error(where + "no such file");
  }
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&skipImage, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool binary = path.extension() == ".glb";
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                         : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
  if (!ok) {
    throw Error(where +
                "not a valid glTF 2.0 file: " + oneLine(err.empty() ? "unknown parse error" : err));
  }
  for (const auto& extension : model.extensionsRequired) {
    if (!ignorableExtension(extension)) {
      throw Error(where + "requires the unsupported extension " + extension);
    }
  }
  if (model.scenes.empty()) throw Error(where + "has no scene");
  const int scene_index = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (scene_index >= static_cast<int>(model.scenes.size())) {
    throw Error(where + "its default scene " + std::to_string(scene_index) + " does not exist");
  }
  Scene scene;
  scene.name = model.scenes[scene_index].name.empty() ? path.stem().string()
                                                      : model.scenes[scene_index].name;
  Reader reader(model, &scene);
  try {
    for (int root : model.scenes[scene_index].nodes) reader.walk(root, std::nullopt, 0);
  } catch (const Error& e) {
    throw Error(where + e.what());
  }
  if (!reader.hasCamera()) {
    throw Error(where + (reader.sawOrthographic()
                             ? "has only orthographic cameras; a perspective camera is required"
                             : "has no camera in its scene; add a perspective camera node"));
  }
  if (scene.triangles.empty()) throw Error(where + "has no triangles in its scene");
  return scene;
}

}  // namespace gtbake
