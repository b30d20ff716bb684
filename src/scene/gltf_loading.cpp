// loadGltfModel: the file rules of readGltfScene (gltf_reader.h, docs/limits.md) around tinygltf.
#include "scene/gltf_loading.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/input_limits.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

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

bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
  return true;  // images never matter to occlusion
}

}  // namespace

tinygltf::Model loadGltfModel(const std::filesystem::path& path, bool allow_outside) {
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
    checkUris(doc, allow_outside);
  } catch (const Error& e) {
    throw Error(where + e.what());
  }
  // Before tinygltf parses the accessors: a Draco-compressed primitive has none of its own, which
  // tinygltf would report as an invalid bufferView.
  if (doc.is_object() && doc.contains("extensionsRequired") &&
      doc["extensionsRequired"].is_array()) {
    for (const auto& extension : doc["extensionsRequired"]) {
      if (extension.is_string() && !ignorableExtension(extension.get<std::string>())) {
        throw Error(where + "unsupported extension " + extension.get<std::string>() +
                    " (required by the file; decompress or convert it to plain glTF 2.0 first)");
      }
    }
  }

  FileAccess access;
  access.base = fs::weakly_canonical(fs::absolute(path).parent_path(), ec);
  access.allow_outside = allow_outside;
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
      throw Error(where + "unsupported extension " + extension + " (required by the file)");
    }
  }
  return model;
}

}  // namespace gtbake
