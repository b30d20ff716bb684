// Fuzz target: readGltfScene on arbitrary bytes, as .gltf (first byte even) or .glb (odd), with
// a sibling buffer file. Anything but a gtbake::Error or a scene is a bug.
#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/error.h"
#include "fuzz_target.h"
#include "scene/gltf_reader.h"
#include "scene/procedural_scenes.h"
#include "support/test_scenes.h"

namespace gtbake::fuzz {

std::vector<std::string> seeds() {
  const std::string dir = scratchDir() + "/seed";
  writeGltfScene(dir + "/box.gltf", makeClosedBoxScene());
  std::vector<std::string> out;
  // Inline the buffer as a data URI so one file carries the whole scene.
  nlohmann::json doc = nlohmann::json::parse(readFile(dir + "/box.gltf"));
  const std::string bin = readFile(dir + "/box.bin");
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string b64;
  for (std::size_t i = 0; i < bin.size(); i += 3) {
    const std::uint32_t n = (static_cast<unsigned char>(bin[i]) << 16) |
                            (i + 1 < bin.size() ? static_cast<unsigned char>(bin[i + 1]) << 8 : 0) |
                            (i + 2 < bin.size() ? static_cast<unsigned char>(bin[i + 2]) : 0);
    b64 += kAlphabet[(n >> 18) & 63];
    b64 += kAlphabet[(n >> 12) & 63];
    b64 += i + 1 < bin.size() ? kAlphabet[(n >> 6) & 63] : '=';
    b64 += i + 2 < bin.size() ? kAlphabet[n & 63] : '=';
  }
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + b64;
  out.push_back(std::string(1, '\0') + doc.dump());
  doc["buffers"][0]["uri"] = "box.bin";  // the external-file path rules
  out.push_back(std::string(1, '\2') + doc.dump());
  return out;
}

}  // namespace gtbake::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gtbake;
  if (size < 1) return 0;
  const std::string dir = fuzz::scratchDir();
  static bool bin_written = false;
  if (!bin_written) {
    writeGltfScene(dir + "/box.gltf", makeClosedBoxScene());
    bin_written = true;
  }
  const std::string path = dir + ((data[0] & 1) ? "/input.glb" : "/input.gltf");
  writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(data) + 1, size - 1));
  try {
    readGltfScene(path, GltfReadOptions{});
  } catch (const Error&) {
  }
  return 0;
}
