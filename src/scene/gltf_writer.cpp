// writeGltfScene: one mesh (float VEC3 positions, u32 indices) on an identity node, the camera on
// a second node whose matrix holds its basis and position exactly, one double-sided white
// material, all in <name>.gltf (JSON, keys sorted, so the bytes are a pure function of the
// scene) and <name>.bin. Both are encoded in memory (tinygltf serializes the JSON to a stream;
// the buffer is ours); `gtbake scenes` stages them in its output set, writeGltfScene writes them
// through the checked atomic writer, .bin first, so a failed write (disk full) is an error and a
// reader never sees a .gltf whose buffer is missing or stale.
#include <tiny_gltf.h>

#include <cstring>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "gtbake_version.h"
#include "scene/scene.h"

namespace gtbake {
namespace {

// Near plane for viewers, m (the sweep ignores it): well below every scene's feature size.
constexpr double kZNear = 0.01;
// Far plane for viewers, m: beyond the 10 km ground of the generated scenes.
constexpr double kZFar = 1.0e5;

// One buffer (positions, then 32-bit indices), its two views and accessors (with the position
// bounds glTF requires).
void addGeometry(const Scene& scene, const std::string& bin_name, tinygltf::Model& model) {
  tinygltf::Buffer buffer;
  buffer.uri = bin_name;
  const std::size_t position_bytes = scene.positions.size() * 12;
  const std::size_t index_bytes = scene.triangles.size() * 12;
  buffer.data.resize(position_bytes + index_bytes);
  for (std::size_t i = 0; i < scene.positions.size(); ++i) {
    std::memcpy(buffer.data.data() + 12 * i, scene.positions[i].data(), 12);
  }
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    std::memcpy(buffer.data.data() + position_bytes + 12 * t, scene.triangles[t].data(), 12);
  }
  model.buffers.push_back(buffer);

  tinygltf::BufferView positions_view;
  positions_view.buffer = 0;
  positions_view.byteOffset = 0;
  positions_view.byteLength = position_bytes;
  positions_view.target = TINYGLTF_TARGET_ARRAY_BUFFER;
  tinygltf::BufferView indices_view;
  indices_view.buffer = 0;
  indices_view.byteOffset = position_bytes;
  indices_view.byteLength = index_bytes;
  indices_view.target = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
  model.bufferViews = {positions_view, indices_view};

  tinygltf::Accessor positions;
  positions.bufferView = 0;
  positions.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  positions.type = TINYGLTF_TYPE_VEC3;
  positions.count = scene.positions.size();
  Eigen::Vector3f lo = Eigen::Vector3f::Zero(), hi = Eigen::Vector3f::Zero();
  if (!scene.positions.empty()) lo = hi = scene.positions.front();
  for (const auto& p : scene.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  positions.minValues = {lo.x(), lo.y(), lo.z()};
  positions.maxValues = {hi.x(), hi.y(), hi.z()};
  tinygltf::Accessor indices;
  indices.bufferView = 1;
  indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  indices.type = TINYGLTF_TYPE_SCALAR;
  indices.count = 3 * scene.triangles.size();
  model.accessors = {positions, indices};
}

// The perspective camera and the two nodes: the mesh, and the camera with its pose as a matrix.
void addCameraAndNodes(const Scene& scene, tinygltf::Model& model) {
  tinygltf::Camera camera;
  camera.type = "perspective";
  camera.name = "camera";
  camera.perspective.yfov = scene.camera.yfov;
  camera.perspective.znear = kZNear;
  camera.perspective.zfar = kZFar;
  model.cameras.push_back(camera);

  tinygltf::Node geometry;
  geometry.name = scene.name;
  geometry.mesh = 0;
  tinygltf::Node camera_node;
  camera_node.name = "camera";
  camera_node.camera = 0;
  camera_node.matrix.assign(16, 0.0);
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) camera_node.matrix[4 * c + r] = scene.camera.basis(r, c);
    camera_node.matrix[12 + c] = scene.camera.position[c];
  }
  camera_node.matrix[15] = 1.0;
  model.nodes = {geometry, camera_node};
}

tinygltf::Model buildModel(const Scene& scene, const std::string& bin_name) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = std::string("gtbake ") + GTBAKE_VERSION;

  addGeometry(scene, bin_name, model);

  tinygltf::Material material;
  material.name = "lambert_white";
  material.doubleSided = true;  // docs/sweep.md §1: every surface is two-sided
  material.pbrMetallicRoughness.baseColorFactor = {1.0, 1.0, 1.0, 1.0};
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 1.0;
  model.materials.push_back(material);

  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = 0;
  primitive.indices = 1;
  primitive.material = 0;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh mesh;
  mesh.name = scene.name;
  mesh.primitives.push_back(primitive);
  model.meshes.push_back(mesh);

  addCameraAndNodes(scene, model);

  tinygltf::Scene gltf_scene;
  gltf_scene.name = scene.name;
  if (!scene.type.empty()) {
    tinygltf::Value::Object extras;
    extras["gtbake_type"] = tinygltf::Value(scene.type);
    gltf_scene.extras = tinygltf::Value(extras);
  }
  gltf_scene.nodes = {0, 1};
  model.scenes.push_back(gltf_scene);
  model.defaultScene = 0;
  return model;
}

}  // namespace

GltfFiles encodeGltfScene(const std::string& stem, const Scene& scene) {
  tinygltf::Model model = buildModel(scene, stem + ".bin");
  // The buffer leaves the model: tinygltf's stream writer would embed it as base64; the JSON
  // entry pointing at the .bin is put back below.
  const std::vector<unsigned char> bin = std::move(model.buffers.front().data);
  model.buffers.clear();
  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/true,
                                     /*writeBinary=*/false)) {
    throw Error(stem + ".gltf: cannot encode the glTF");
  }
  nlohmann::json doc = nlohmann::json::parse(stream.str());
  doc["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}, {"uri", stem + ".bin"}}});
  return {doc.dump(2) + "\n", std::string(reinterpret_cast<const char*>(bin.data()), bin.size())};
}

void writeGltfScene(const std::filesystem::path& path, const Scene& scene) {
  namespace fs = std::filesystem;
  if (path.extension() != ".gltf") {
    throw Error(path.string() + ": the scene must be written as .gltf (JSON plus .bin)");
  }
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  ensureDirectory(dir);
  const std::string stem = path.stem().string();
  const GltfFiles files = encodeGltfScene(stem, scene);
  writeFileAtomically(dir / (stem + ".bin"), files.bin);
  writeFileAtomically(path, files.gltf);
}

}  // namespace gtbake
