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
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <set>

#include "common/checked_math.h"
#include "common/error.h"
#include "common/input_limits.h"
#include "common/math_constants.h"
#include "scene/gltf_loading.h"
#include "scene/gltf_reader.h"

namespace gtbake {
namespace {

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

// glTF 2.0 §3.7.2.1: strip triangle i is (v_i, v_{i+1+i%2}, v_{i+2−i%2}) (every other one
// reversed so all keep the first one's winding), fan triangle i is (v_{i+1}, v_{i+2}, v_0).
// Triangles that repeat a vertex (the degenerate joints of stitched strips) are dropped.
std::vector<std::uint32_t> triangulateStripOrFan(const std::vector<std::uint32_t>& v, bool strip) {
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i + 2 < v.size(); ++i) {
    const std::uint32_t a = strip ? v[i] : v[i + 1];
    const std::uint32_t b = strip ? v[i + 1 + i % 2] : v[i + 2];
    const std::uint32_t c = strip ? v[i + 2 - i % 2] : v[0];
    if (a == b || b == c || c == a) continue;
    out.insert(out.end(), {a, b, c});
  }
  return out;
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

// Coordinates beyond this many metres (vertices, camera positions) are refused: float32 keeps
// under 0.1 m of resolution there and Embree's own asserts trip near 1e18.
inline constexpr Limit kMaxCoordinate{"GTBAKE_MAX_COORDINATE", 1'000'000, "metres"};

struct CameraInstance {
  int node = -1;
  int camera = -1;
  Eigen::Matrix4d world;
};

class Reader {
 public:
  Reader(const tinygltf::Model& model, Scene* scene)
      : model_(model),
        scene_(scene),
        max_coordinate_(static_cast<double>(limitValue(kMaxCoordinate))),
        max_triangles_(limitValue(kMaxTriangles)),
        max_vertices_(limitValue(kMaxVertices)) {}

  // Depth-first, parents before children, children in order, with an explicit stack: a deep
  // chain cannot overflow the call stack, and every instance pushed is counted against
  // kMaxInstances (a node listed twice as a child doubles the instances below it).
  void walk(const std::vector<int>& roots) {
    struct Pending {
      int node;
      Eigen::Matrix4d parent;
      std::size_t depth;
    };
    std::vector<Pending> stack;
    const std::uint64_t max_instances = limitValue(kMaxInstances);
    std::uint64_t instances = 0;
    auto push = [&](int node, const Eigen::Matrix4d& parent, std::size_t depth) {
      if (node < 0 || node >= static_cast<int>(model_.nodes.size())) {
        throw Error("node index " + std::to_string(node) + " is out of range");
      }
      if (depth > model_.nodes.size()) {
        throw Error("the node hierarchy has a cycle (through node " + std::to_string(node) + ")");
      }
      if (++instances > max_instances) checkLimit(kMaxInstances, instances, "the node hierarchy");
      stack.push_back({node, parent, depth});
    };
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) {
      push(*it, Eigen::Matrix4d::Identity(), 0);
    }
    while (!stack.empty()) {
      const Pending item = stack.back();
      stack.pop_back();
      const tinygltf::Node& node = model_.nodes[static_cast<std::size_t>(item.node)];
      const Eigen::Matrix4d world = item.parent * localTransform(node);
      if (!world.allFinite()) {
        throw Error("node " + std::to_string(item.node) + " has a non-finite transform");
      }
      if (node.mesh >= 0) addMesh(node.mesh, world);
      if (node.camera >= 0) addCamera(item.node, node.camera, world);
      for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) {
        push(*it, world, item.depth + 1);
      }
    }
  }

  const std::vector<std::string>& orthographicCameras() const { return ignored_; }
  const std::vector<CameraInstance>& cameras() const { return cameras_; }

  // Places the chosen camera; throws for a degenerate, mirrored or absurdly placed one.
  void useCamera(const CameraInstance& instance) {
    const std::string what = "camera " + std::to_string(instance.camera) + " (node " +
                             std::to_string(instance.node) + ")";
    const tinygltf::Camera& camera = model_.cameras[static_cast<std::size_t>(instance.camera)];
    if (!(camera.perspective.yfov > 0.0 && camera.perspective.yfov < kPi)) {
      throw Error(what + " has an invalid yfov");
    }
    Eigen::Matrix3d basis = instance.world.topLeftCorner<3, 3>();
    const double det = basis.determinant();
    if (!(std::abs(det) > 1e-12 * std::pow(basis.cwiseAbs().maxCoeff(), 3)) || !(det > 0.0)) {
      throw Error(what + (det < 0.0 ? " has a mirroring (negative-determinant) transform"
                                    : " has a zero scale (its transform is singular)"));
    }
    const Eigen::Vector3d position = instance.world.block<3, 1>(0, 3);
    if (!position.allFinite() || position.cwiseAbs().maxCoeff() > max_coordinate_) {
      throw Error(what + " is placed beyond " + std::to_string(max_coordinate_) +
                  " m from the origin (set " + kMaxCoordinate.env + " to raise the limit)");
    }
    // Columns of the world matrix, scale removed; left bit-exact when already orthonormal so a
    // written camera reads back identical.
    const double kTolerance = 1e-12;
    if (!(basis.transpose() * basis).isIdentity(kTolerance)) {
      basis.col(0).normalize();
      basis.col(1) -= basis.col(0).dot(basis.col(1)) * basis.col(0);
      basis.col(1).normalize();
      basis.col(2) = basis.col(0).cross(basis.col(1));
      if (!basis.allFinite()) throw Error(what + " has a degenerate transform");
    }
    scene_->camera.position = position;
    scene_->camera.basis = basis;
    scene_->camera.yfov = camera.perspective.yfov;
  }

 private:
  // Start of an accessor's data after checking, in 64-bit arithmetic that cannot wrap, that
  // every element lies inside its buffer view and the view inside its buffer.
  const unsigned char* element(const tinygltf::Accessor& accessor, std::size_t element_size,
                               const std::string& what, std::size_t* stride_out) const {
    if (accessor.sparse.isSparse) throw Error(what + " uses a sparse accessor (unsupported)");
    if (accessor.bufferView < 0 ||
        accessor.bufferView >= static_cast<int>(model_.bufferViews.size())) {
      throw Error(what + " has no buffer view");
    }
    const tinygltf::BufferView& view =
        model_.bufferViews[static_cast<std::size_t>(accessor.bufferView)];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model_.buffers.size())) {
      throw Error(what + " refers to a missing buffer");
    }
    const tinygltf::Buffer& buffer = model_.buffers[static_cast<std::size_t>(view.buffer)];
    const std::uint64_t stride = view.byteStride ? view.byteStride : element_size;
    if (stride < element_size) throw Error(what + " has a byteStride smaller than its element");
    const std::uint64_t view_end = checkedAdd(view.byteOffset, view.byteLength, what);
    const std::uint64_t begin = checkedAdd(view.byteOffset, accessor.byteOffset, what);
    const std::uint64_t end =
        accessor.count == 0
            ? begin
            : checkedAdd(checkedAdd(begin, checkedMul(accessor.count - 1, stride, what), what),
                         element_size, what);
    if (end > view_end || view_end > buffer.data.size()) {
      throw Error(what + " reads past the end of its buffer view or buffer");
    }
    *stride_out = static_cast<std::size_t>(stride);
    return buffer.data.data() + begin;
  }

  // The u8/u16/u32 indices of `acc`, each checked against the vertex count.
  std::vector<std::uint32_t> readIndices(const tinygltf::Accessor& acc, std::size_t vertices,
                                         const std::string& what) const {
    const int size = acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                     : acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                     : acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                                   : 0;
    if (size == 0 || acc.type != TINYGLTF_TYPE_SCALAR) {
      throw Error(what + " indices are not unsigned 8-, 16- or 32-bit scalars");
    }
    std::size_t stride = 0;
    const unsigned char* data =
        element(acc, static_cast<std::size_t>(size), what + " indices", &stride);
    std::vector<std::uint32_t> indices;
    indices.reserve(acc.count);
    for (std::size_t i = 0; i < acc.count; ++i) {
      std::uint32_t v = 0;
      if (size == 1) v = data[i * stride];
      if (size == 2) {
        std::uint16_t s;
        std::memcpy(&s, data + i * stride, 2);
        v = s;
      }
      if (size == 4) std::memcpy(&v, data + i * stride, 4);
      if (v >= vertices) {
        throw Error(what + " has index " + std::to_string(v) + " but only " +
                    std::to_string(vertices) + " vertices");
      }
      indices.push_back(v);
    }
    return indices;
  }

  void addMesh(int mesh_index, const Eigen::Matrix4d& world) {
    if (mesh_index >= static_cast<int>(model_.meshes.size())) {
      throw Error("mesh index " + std::to_string(mesh_index) + " is out of range");
    }
    const tinygltf::Mesh& mesh = model_.meshes[static_cast<std::size_t>(mesh_index)];
    const bool mirrored = world.topLeftCorner<3, 3>().determinant() < 0.0;
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const tinygltf::Primitive& prim = mesh.primitives[p];
      const std::string what = "mesh " + std::to_string(mesh_index) + " ('" + mesh.name +
                               "') primitive " + std::to_string(p);
      const bool strip = prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP;
      const bool fan = prim.mode == TINYGLTF_MODE_TRIANGLE_FAN;
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1 && !strip && !fan) {
        throw Error(what + " has mode " + modeName(prim.mode) +
                    "; only TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN primitives are supported");
      }
      const auto position = prim.attributes.find("POSITION");
      if (position == prim.attributes.end() || position->second < 0 ||
          position->second >= static_cast<int>(model_.accessors.size())) {
        throw Error(what + " has no POSITION attribute");
      }
      const tinygltf::Accessor& pos = model_.accessors[static_cast<std::size_t>(position->second)];
      if (pos.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || pos.type != TINYGLTF_TYPE_VEC3) {
        throw Error(what + " POSITION is not float VEC3 (quantized positions are unsupported)");
      }
      std::size_t pos_stride = 0;
      const unsigned char* pos_data = element(pos, 12, what + " POSITION", &pos_stride);
      const std::uint64_t vertices = checkedAdd(scene_->positions.size(), pos.count, what);
      if (vertices > max_vertices_) checkLimit(kMaxVertices, vertices, "the scene");
      const auto base = static_cast<std::uint32_t>(scene_->positions.size());
      for (std::size_t i = 0; i < pos.count; ++i) {
        float xyz[3];
        std::memcpy(xyz, pos_data + i * pos_stride, sizeof(xyz));
        const Eigen::Vector4d p4 = world * Eigen::Vector4d(xyz[0], xyz[1], xyz[2], 1.0);
        const Eigen::Vector3f q = p4.head<3>().cast<float>();
        if (!q.allFinite()) throw Error(what + " has a non-finite vertex position");
        if (p4.head<3>().cwiseAbs().maxCoeff() > max_coordinate_) {
          throw Error(what + " has a vertex beyond " + std::to_string(max_coordinate_) +
                      " m from the origin (set " + kMaxCoordinate.env + " to raise the limit)");
        }
        scene_->positions.push_back(q);
      }
      std::vector<std::uint32_t> indices;
      const std::size_t index_count = prim.indices >= 0 ? [&] {
        if (prim.indices >= static_cast<int>(model_.accessors.size())) {
          throw Error(what + " indices accessor is out of range");
        }
        return model_.accessors[static_cast<std::size_t>(prim.indices)].count;
      }()
                                                        : pos.count;
      const std::size_t new_triangles =
          strip || fan ? (index_count >= 3 ? index_count - 2 : 0) : index_count / 3;
      const std::uint64_t triangles = checkedAdd(scene_->triangles.size(), new_triangles, what);
      if (triangles > max_triangles_) checkLimit(kMaxTriangles, triangles, "the scene");
      if (prim.indices >= 0) {
        indices =
            readIndices(model_.accessors[static_cast<std::size_t>(prim.indices)], pos.count, what);
      } else {
        indices.reserve(pos.count);
        for (std::size_t i = 0; i < pos.count; ++i) {
          indices.push_back(static_cast<std::uint32_t>(i));
        }
      }
      if (strip || fan) {
        indices = triangulateStripOrFan(indices, strip);
      } else if (indices.size() % 3 != 0) {
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

  void addCamera(int node_index, int camera_index, const Eigen::Matrix4d& world) {
    if (camera_index >= static_cast<int>(model_.cameras.size())) {
      throw Error("camera index " + std::to_string(camera_index) + " is out of range");
    }
    const tinygltf::Camera& camera = model_.cameras[static_cast<std::size_t>(camera_index)];
    if (camera.type != "perspective") {
      const std::string& node = model_.nodes[static_cast<std::size_t>(node_index)].name;
      ignored_.push_back(!camera.name.empty() ? camera.name
                         : !node.empty()      ? node
                                              : "camera " + std::to_string(camera_index));
      return;
    }
    cameras_.push_back({node_index, camera_index, world});
  }

  const tinygltf::Model& model_;
  Scene* scene_;
  double max_coordinate_;
  std::uint64_t max_triangles_;
  std::uint64_t max_vertices_;
  std::vector<CameraInstance> cameras_;
  std::vector<std::string> ignored_;  // names of the orthographic camera instances
};

// Index of the camera instance `wanted` names (see GltfReadOptions::camera).
std::size_t chooseCamera(const tinygltf::Model& model, const std::vector<CameraInstance>& cameras,
                         const std::string& wanted) {
  if (wanted.empty()) return 0;
  if (wanted.find_first_not_of("0123456789") == std::string::npos && wanted.size() < 9) {
    const std::size_t index = std::stoul(wanted);
    if (index >= cameras.size()) {
      throw Error("--camera " + wanted + ": the scene has " + std::to_string(cameras.size()) +
                  " perspective camera(s), numbered from 0");
    }
    return index;
  }
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const auto& c = cameras[i];
    if (model.cameras[static_cast<std::size_t>(c.camera)].name == wanted ||
        model.nodes[static_cast<std::size_t>(c.node)].name == wanted) {
      return i;
    }
  }
  throw Error("--camera " + wanted + ": no perspective camera or camera node has that name");
}

// Places the camera `wanted` names and records which one it was.
void useChosenCamera(const tinygltf::Model& model, Reader& reader, const std::string& wanted,
                     GltfReadInfo* info) {
  const std::size_t chosen = chooseCamera(model, reader.cameras(), wanted);
  reader.useCamera(reader.cameras()[chosen]);
  if (info != nullptr) {
    const CameraInstance& c = reader.cameras()[chosen];
    info->perspective_cameras = static_cast<int>(reader.cameras().size());
    info->camera_instance = static_cast<int>(chosen);
    const std::string& camera_name = model.cameras[static_cast<std::size_t>(c.camera)].name;
    info->camera_name =
        camera_name.empty() ? model.nodes[static_cast<std::size_t>(c.node)].name : camera_name;
  }
}

}  // namespace

Scene readGltfScene(const std::filesystem::path& path, const GltfReadOptions& options,
                    GltfReadInfo* info) {
  const std::string where = path.string() + ": ";
  std::string input_sha256;
  const tinygltf::Model model = loadGltfModel(path, options.allow_outside, &input_sha256);
  if (model.scenes.empty()) throw Error(where + "has no scene");
  const int scene_index = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (scene_index >= static_cast<int>(model.scenes.size())) {
    throw Error(where + "its default scene " + std::to_string(scene_index) + " does not exist");
  }
  Scene scene;
  scene.name = model.scenes[static_cast<std::size_t>(scene_index)].name.empty()
                   ? path.stem().string()
                   : model.scenes[static_cast<std::size_t>(scene_index)].name;
  const tinygltf::Value& extras = model.scenes[static_cast<std::size_t>(scene_index)].extras;
  if (extras.IsObject() && extras.Has("gtbake_type") && extras.Get("gtbake_type").IsString()) {
    scene.type = extras.Get("gtbake_type").Get<std::string>();
  }
  Reader reader(model, &scene);
  try {
    reader.walk(model.scenes[static_cast<std::size_t>(scene_index)].nodes);
    if (reader.cameras().empty() && options.allow_no_camera) {
      if (info != nullptr) *info = GltfReadInfo{};
    } else if (reader.cameras().empty()) {
      throw Error(!reader.orthographicCameras().empty()
                      ? "has only orthographic cameras; a perspective camera is required"
                      : "has no camera in its scene; add a perspective camera node");
    } else {
      useChosenCamera(model, reader, options.camera, info);
    }
  } catch (const Error& e) {
    throw Error(where + e.what());
  }
  if (scene.triangles.empty()) throw Error(where + "has no triangles in its scene");
  if (info != nullptr) {
    info->input_sha256 = input_sha256;
    info->orthographic_cameras = reader.orthographicCameras();
  }
  return scene;
}
Scene readGltfScene(const std::filesystem::path& path) {
  GltfReadInfo info;
  Scene scene = readGltfScene(path, GltfReadOptions{}, &info);
  if (info.perspective_cameras > 1) {
    std::fprintf(stderr,
                 "gtbake: note: %s has %d perspective cameras; using the first, '%s' (choose "
                 "with --camera NAME|INDEX)\n",
                 path.string().c_str(), info.perspective_cameras, info.camera_name.c_str());
  }
  return scene;
}

}  // namespace gtbake
