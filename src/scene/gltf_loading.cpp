// loadGltfModel: the file rules of readGltfScene (gltf_reader.h, docs/limits.md) around tinygltf.
#include "scene/gltf_loading.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/input_limits.h"
#include "common/sha256.h"

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
// allowed), regular files only, never the current directory (tinygltf tries "./uri" last), and
// only the buffers: images never matter to occlusion, so they are never opened (a huge or
// unreadable texture cannot fail a sweep). Every file read is recorded for the scene's hash.
struct ExternalBuffer {
  std::string uri;         // as written in the glTF
  std::uint64_t size = 0;  // its byteLength: a larger file is refused before it is read
};
struct FileAccess {
  fs::path base;  // canonical directory of the glTF
  bool allow_outside = false;
  std::map<std::string, ExternalBuffer> buffers;  // by resolved path (base / decoded uri)
  std::string record;  // one line per file read, hashed into the scene's input_sha256
};

// The uri handed to tinygltf for an external buffer: what percentDecode makes of `uri`, every
// byte but [A-Za-z0-9._~/-] percent-encoded again. tinygltf's own decoding (dlib::urldecode)
// also turns '+' into a space and "%zz" into a NUL, which RFC 3986 does not; on this form it
// yields exactly the file percentDecode names, so "a+b.bin" is read as "a+b.bin" and never as
// "a b.bin" (docs/limits.md §Paths).
std::string tinygltfUri(const std::string& uri) {
  static const char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (const char c : percentDecode(uri)) {
    const auto byte = static_cast<unsigned char>(c);
    if (std::isalnum(byte) || c == '.' || c == '_' || c == '~' || c == '/' || c == '-') {
      out.push_back(c);
    } else {
      out += {'%', kHex[byte >> 4], kHex[byte & 15]};
    }
  }
  return out;
}

// tinygltf joins the glTF's directory and the decoded tinygltfUri, i.e. percentDecode(uri), as
// "<base>/<file>"; the buffer's resolved path is base / file (the same but for an absolute file,
// which allow_outside allows).
std::string expandFilePath(const std::string& path, void* user) {
  const auto* access = static_cast<const FileAccess*>(user);
  std::string prefix = access->base.string();  // as tinygltf's JoinPath joins it
  if (!prefix.empty() && prefix.back() != '/') prefix += '/';
  for (const auto& [resolved, buffer] : access->buffers) {
    if (path == prefix + percentDecode(buffer.uri)) return resolved;
  }
  return path;
}

// The buffer the resolved `path` names, or nullptr (an image, the cwd fallback).
const ExternalBuffer* knownBuffer(const std::string& path, const FileAccess& access) {
  const auto it = access.buffers.find(path);
  return it == access.buffers.end() ? nullptr : &it->second;
}

bool fileExists(const std::string& path, void* user) {
  std::error_code ec;
  return knownBuffer(path, *static_cast<const FileAccess*>(user)) != nullptr &&
         fs::exists(fs::path(path), ec);
}

// Reads a buffer: inside the glTF's directory also after symbolic links (unless allowed), a
// regular file of at most its byteLength; recorded for the scene's hash.
bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                   void* user) {
  auto* access = static_cast<FileAccess*>(user);
  try {
    const ExternalBuffer* buffer = knownBuffer(path, *access);
    if (buffer == nullptr) throw Error(path + " is not one of the glTF's buffers");
    std::error_code ec;
    const fs::path resolved = fs::weakly_canonical(fs::path(path), ec);
    const fs::path relative = resolved.lexically_relative(access->base);
    if (!access->allow_outside && (ec || relative.empty() || *relative.begin() == "..")) {
      throw Error("buffer uri '" + buffer->uri + "' leaves the glTF's directory (through a " +
                  "symbolic link)");
    }
    const std::string bytes = readRegularFile(path, buffer->size);
    access->record +=
        buffer->uri + " " + std::to_string(bytes.size()) + " " + sha256Hex(bytes) + "\n";
    out->assign(bytes.begin(), bytes.end());
    return true;
  } catch (const Error& e) {
    if (err) *err = e.what();
    return false;
  }
}

// The glTF's external buffers (not data: uris), resolved against `base`.
std::map<std::string, ExternalBuffer> externalBuffers(const nlohmann::json& doc,
                                                      const fs::path& base) {
  std::map<std::string, ExternalBuffer> buffers;
  if (!doc.is_object() || !doc.contains("buffers") || !doc["buffers"].is_array()) return buffers;
  for (const nlohmann::json& b : doc["buffers"]) {
    if (!b.is_object() || !b.contains("uri") || !b["uri"].is_string()) continue;
    ExternalBuffer buffer;
    buffer.uri = b["uri"].get<std::string>();
    if (buffer.uri.rfind("data:", 0) == 0) continue;
    const auto& length = b.contains("byteLength") ? b["byteLength"] : nlohmann::json();
    buffer.size = length.is_number_unsigned() ? length.get<std::uint64_t>() : 0;
    buffers.emplace((base / percentDecode(buffer.uri)).string(), buffer);
  }
  return buffers;
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

// glTF 1.0 is not glTF 2.0: tinygltf reports it as a missing "asset" or a scene-less file. It is
// told by its asset.version "1.x", by its dictionaries where 2.0 has arrays (1.0 keys every
// object by id) or, for a .glb, by container version 1.
void refuseGltf1(const nlohmann::json& doc, const std::string& bytes, bool binary) {
  std::uint32_t container = 2;
  if (binary && bytes.size() >= 8 && bytes.compare(0, 4, "glTF") == 0) {
    std::memcpy(&container, bytes.data() + 4, 4);
  }
  bool v1 = container == 1;
  if (doc.is_object()) {
    const auto asset = doc.find("asset");
    v1 = v1 || (asset != doc.end() && asset->is_object() && asset->contains("version") &&
                (*asset)["version"].is_string() &&
                (*asset)["version"].get<std::string>().rfind("1.", 0) == 0);
    for (const char* key : {"accessors", "bufferViews", "buffers", "meshes", "nodes", "scenes"}) {
      v1 = v1 || (doc.contains(key) && doc[key].is_object());
    }
  }
  if (!v1) return;
  if (container == 1) {
    throw Error(
        "binary glTF 1.0 (.glb version 1) is not supported, only glTF 2.0: convert it to "
        "glTF 2.0 first (Debian's assimp 5.2 cannot read it)");
  }
  throw Error(
      "glTF 1.0 is not supported, only glTF 2.0: convert it first, e.g. with `assimp "
      "export in.gltf out.gltf -f gltf2` (Debian package assimp-utils)");
}

// The bytes handed to tinygltf: the file itself, or, when an external buffer's uri is not
// already in tinygltfUri's form, the document with those uris rewritten (a .glb keeps its
// header and every chunk after the JSON).
std::string tinygltfInput(const std::string& bytes, bool binary, nlohmann::json doc) {
  bool rewritten = false;
  if (doc.is_object() && doc.contains("buffers") && doc["buffers"].is_array()) {
    for (nlohmann::json& b : doc["buffers"]) {
      if (!b.is_object() || !b.contains("uri") || !b["uri"].is_string()) continue;
      const std::string uri = b["uri"].get<std::string>();
      if (uri.rfind("data:", 0) == 0 || tinygltfUri(uri) == uri) continue;
      b["uri"] = tinygltfUri(uri);
      rewritten = true;
    }
  }
  if (!rewritten) return bytes;
  std::string text = doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (!binary) return text;
  text.append((4 - text.size() % 4) % 4, ' ');
  const std::string rest = bytes.substr(20 + jsonText(bytes, true).size());
  const auto u32 = [](std::size_t v) {
    const auto value = static_cast<std::uint32_t>(v);
    return std::string(reinterpret_cast<const char*>(&value), 4);
  };
  return bytes.substr(0, 8) + u32(20 + text.size() + rest.size()) + u32(text.size()) + "JSON" +
         text + rest;
}

bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
  return true;  // images never matter to occlusion (embedded ones are not decoded either)
}

}  // namespace

namespace {

// The glTF's JSON document, checked before tinygltf sees it: nesting depth, glTF 1.0, uris that
// leave the directory, and required extensions (a Draco-compressed primitive has no accessors
// of its own, which tinygltf would report as an invalid bufferView). Errors lack the path.
nlohmann::json checkedDocument(const std::string& bytes, bool binary, bool allow_outside) {
  const auto max_depth = static_cast<int>(limitValue(kMaxJsonDepth));
  const std::string_view json_text = jsonText(bytes, binary);
  if (jsonNestingDepth(json_text, max_depth) > max_depth) {
    throw Error("JSON nested deeper than " + std::to_string(max_depth) + " levels (set " +
                kMaxJsonDepth.env + " to raise the limit)");
  }
  nlohmann::json doc = nlohmann::json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  refuseGltf1(doc, bytes, binary);
  checkUris(doc, allow_outside);
  if (doc.is_object() && doc.contains("extensionsRequired") &&
      doc["extensionsRequired"].is_array()) {
    for (const auto& extension : doc["extensionsRequired"]) {
      if (extension.is_string() && !ignorableExtension(extension.get<std::string>())) {
        throw Error("unsupported extension " + extension.get<std::string>() +
                    " (required by the file; decompress or convert it to plain glTF 2.0 first)");
      }
    }
  }
  return doc;
}

}  // namespace

tinygltf::Model loadGltfModel(const std::filesystem::path& path, bool allow_outside,
                              std::string* input_sha256) {
  const std::string where = path.string() + ": ";
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw Error(where + (fs::exists(path, ec) ? "not a regular file" : "no such file"));
  }
  const std::string bytes = readRegularFile(path);
  const bool binary = path.extension() == ".glb";
  if (binary && bytes.size() > 0xFFFFFFFFu) throw Error(where + "a .glb is limited to 4 GB");
  nlohmann::json doc;
  try {
    doc = checkedDocument(bytes, binary, allow_outside);
  } catch (const Error& e) {
    throw Error(where + e.what());
  }
  FileAccess access;
  access.base = fs::weakly_canonical(fs::absolute(path).parent_path(), ec);
  access.allow_outside = allow_outside;
  access.buffers = externalBuffers(doc, access.base);
  access.record =
      path.filename().string() + " " + std::to_string(bytes.size()) + " " + sha256Hex(bytes) + "\n";
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
  const std::string input = tinygltfInput(bytes, binary, std::move(doc));
  const bool ok =
      binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                           reinterpret_cast<const unsigned char*>(input.data()),
                                           static_cast<unsigned int>(input.size()), base_dir)
             : loader.LoadASCIIFromString(&model, &err, &warn, input.data(),
                                          static_cast<unsigned int>(input.size()), base_dir);
  if (!ok) {
    throw Error(where +
                "not a valid glTF 2.0 file: " + oneLine(err.empty() ? "unknown parse error" : err));
  }
  for (const auto& extension : model.extensionsRequired) {
    if (!ignorableExtension(extension)) {
      throw Error(where + "unsupported extension " + extension + " (required by the file)");
    }
  }
  if (input_sha256 != nullptr) *input_sha256 = sha256Hex(access.record);
  return model;
}

}  // namespace gtbake
