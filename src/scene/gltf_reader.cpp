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
#include "scene/gltf_reader.h"

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

  bool sawOrthographic() const { return saw_orthographic_; }
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
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) {
        throw Error(what + " has mode " + modeName(prim.mode) +
                    "; only TRIANGLES primitives are supported");
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
      const std::uint64_t triangles = checkedAdd(scene_->triangles.size(), index_count / 3, what);
      if (triangles > max_triangles_) checkLimit(kMaxTriangles, triangles, "the scene");
      if (prim.indices >= 0) {
        const tinygltf::Accessor& acc = model_.accessors[static_cast<std::size_t>(prim.indices)];
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
          if (v >= pos.count) {
            throw Error(what + " has index " + std::to_string(v) + " but only " +
                        std::to_string(pos.count) + " vertices");
          }
          indices.push_back(v);
        }
      } else {
        indices.reserve(pos.count);
        for (std::size_t i = 0; i < pos.count; ++i) {
          indices.push_back(static_cast<std::uint32_t>(i));
        }
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

  void addCamera(int node_index, int camera_index, const Eigen::Matrix4d& world) {
    if (camera_index >= static_cast<int>(model_.cameras.size())) {
      throw Error("camera index " + std::to_string(camera_index) + " is out of range");
    }
    if (model_.cameras[static_cast<std::size_t>(camera_index)].type != "perspective") {
      saw_orthographic_ = true;
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
  bool saw_orthographic_ = false;
};

// File access for tinygltf: external files only below the glTF's own directory (unless
// allowed), regular files only, never the current directory (tinygltf tries "./uri" last).
struct FileAccess {
  std::filesystem::path base;  // canonical directory of the glTF
  bool allow_outside = false;
};

bool fileExists(const std::string& path, void* user) {
  namespace fs = std::filesystem;
  const auto* access = static_cast<const FileAccess*>(user);
  const fs::path p(path);
  if (!p.is_absolute()) return false;  // the cwd fallback
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(p, ec);
  if (ec) return false;
  if (!access->allow_outside) {
    const fs::path relative = resolved.lexically_relative(access->base);
    if (relative.empty() || *relative.begin() == "..") return false;
  }
  return fs::exists(resolved, ec);
}

std::string expandFilePath(const std::string& path, void*) {
  return path;
}

bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                   void*) {
  try {
    const std::string bytes = readRegularFile(path);
    out->assign(bytes.begin(), bytes.end());
    return true;
  } catch (const Error& e) {
    if (err) *err = e.what();
    return false;
  }
}

bool refuseWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err = "the reader never writes";
  return false;
}

// Refuses, before tinygltf opens anything, a buffer or image uri that leaves the directory.
void checkUris(const nlohmann::json& doc, bool allow_outside) {
  if (allow_outside || !doc.is_object()) return;
  for (const char* kind : {"buffers", "images"}) {
    if (!doc.contains(kind) || !doc[kind].is_array()) continue;
    for (std::size_t i = 0; i < doc[kind].size(); ++i) {
      const nlohmann::json& item = doc[kind][i];
      if (!item.is_object() || !item.contains("uri") || !item["uri"].is_string()) continue;
      const std::string uri = item["uri"].get<std::string>();
      if (uri.rfind("data:", 0) == 0) continue;
      const std::string what = std::string(kind) + "[" + std::to_string(i) + "] uri '" + uri + "'";
      const std::string decoded = percentDecode(uri);
      if (decoded.find("://") != std::string::npos) {
        throw Error(what + " is a URL; only files beside the glTF can be read");
      }
      const std::filesystem::path path(decoded);
      if (path.is_absolute() || std::filesystem::path(uri).is_absolute()) {
        throw Error(what + " is an absolute path; external files must lie in the glTF's directory");
      }
      for (const auto& component : path) {
        if (component == "..") {
          throw Error(what + " points outside the glTF's directory ('..' is not allowed)");
        }
      }
    }
  }
}

// The JSON text of a .gltf, or the JSON chunk of a .glb (empty if the header is malformed:
// tinygltf then reports it).
std::string_view jsonText(const std::string& bytes, bool binary) {
  if (!binary) return bytes;
  if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0) return {};
  std::uint32_t chunk_length = 0;
  std::memcpy(&chunk_length, bytes.data() + 12, 4);
  if (chunk_length > bytes.size() - 20) return {};
  return std::string_view(bytes).substr(20, chunk_length);
}

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

bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
  return true;  // images never matter to occlusion
}

}  // namespace

Scene readGltfScene(const std::filesystem::path& path, const GltfReadOptions& options,
                    GltfReadInfo* info) {
  namespace fs = std::filesystem;
  const std::string where = path.string() + ": ";
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw Error(where + (fs::exists(path, ec) ? "not a regular file" : "no such file"));
  }
  const std::string bytes = readRegularFile(path);
  const bool binary = path.extension() == ".glb";
  if (binary && bytes.size() > 0xFFFFFFFFu) throw Error(where + "a .glb is limited to 4 GB");
  const auto max_depth =
      static_cast<int>(std::min<std::uint64_t>(limitValue(kMaxJsonDepth), 1 << 20));
  const std::string_view json_text = jsonText(bytes, binary);
  if (jsonNestingDepth(json_text, max_depth) > max_depth) {
    throw Error(where + "JSON nested deeper than " + std::to_string(max_depth) + " levels (set " +
                kMaxJsonDepth.env + " to raise the limit)");
  }
  const nlohmann::json doc = nlohmann::json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  try {
    checkUris(doc, options.allow_outside);
  } catch (const Error& e) {
    throw Error(where + e.what());
  }

  FileAccess access;
  access.base = fs::weakly_canonical(fs::absolute(path).parent_path(), ec);
  access.allow_outside = options.allow_outside;
  tinygltf::FsCallbacks callbacks{};
  callbacks.FileExists = &fileExists;
  callbacks.ExpandFilePath = &expandFilePath;
  callbacks.ReadWholeFile = &readWholeFile;
  callbacks.WriteWholeFile = &refuseWrite;
  callbacks.user_data = &access;
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks(callbacks);
  loader.SetImageLoader(&skipImage, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const std::string base_dir = access.base.string();
  const bool ok =
      binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                           reinterpret_cast<const unsigned char*>(bytes.data()),
                                           static_cast<unsigned int>(bytes.size()), base_dir)
             : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                          static_cast<unsigned int>(bytes.size()), base_dir);
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
  scene.name = model.scenes[static_cast<std::size_t>(scene_index)].name.empty()
                   ? path.stem().string()
                   : model.scenes[static_cast<std::size_t>(scene_index)].name;
  Reader reader(model, &scene);
  try {
    reader.walk(model.scenes[static_cast<std::size_t>(scene_index)].nodes);
    if (reader.cameras().empty()) {
      throw Error(reader.sawOrthographic()
                      ? "has only orthographic cameras; a perspective camera is required"
                      : "has no camera in its scene; add a perspective camera node");
    }
    const std::size_t chosen = chooseCamera(model, reader.cameras(), options.camera);
    reader.useCamera(reader.cameras()[chosen]);
    if (info != nullptr) {
      const CameraInstance& c = reader.cameras()[chosen];
      info->perspective_cameras = static_cast<int>(reader.cameras().size());
      info->camera_instance = static_cast<int>(chosen);
      const std::string& camera_name = model.cameras[static_cast<std::size_t>(c.camera)].name;
      info->camera_name =
          camera_name.empty() ? model.nodes[static_cast<std::size_t>(c.node)].name : camera_name;
    }
  } catch (const Error& e) {
    throw Error(where + e.what());
  }
  if (scene.triangles.empty()) throw Error(where + "has no triangles in its scene");
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
