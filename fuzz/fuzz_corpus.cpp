// Fuzz target: the corpus descriptions (scene_corpus.h): a scene is the pure function
// makeCorpusScene(type, variant, seed) of what `gtbake scenes` and the glTF extras name. The
// input is one byte picking the type (the twelve names, or else the rest of the input as a type
// name), four bytes of variant (any int, negative too) and eight of seed. A returned scene must be
// named "<type>_<variant>", carry its type, and hold finite positions and triangles indexing
// them; anything else, or an exception other than a gtbake::Error, is a bug.
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "common/error.h"
#include "fuzz_target.h"
#include "scene/scene_corpus.h"

namespace gtbake::fuzz {

namespace {

constexpr std::size_t kHeader = 1 + 4 + 8;

void checkScene(const Scene& scene, const std::string& type, int variant) {
  bool ok = scene.name == type + "_" + std::to_string(variant) && scene.type == type &&
            !scene.triangles.empty();
  for (const auto& p : scene.positions) ok = ok && p.allFinite();
  for (const auto& t : scene.triangles) {
    for (const std::uint32_t v : t) ok = ok && v < scene.positions.size();
  }
  if (!ok) std::abort();  // a malformed scene from a valid description
}

std::string header(std::uint8_t type, std::int32_t variant, std::uint64_t seed) {
  std::string bytes(kHeader, '\0');
  bytes[0] = static_cast<char>(type);
  std::memcpy(bytes.data() + 1, &variant, 4);
  std::memcpy(bytes.data() + 5, &seed, 8);
  return bytes;
}

}  // namespace

std::vector<std::string> seeds() {
  std::vector<std::string> out;
  for (std::uint8_t t = 0; t < corpusTypeNames().size(); ++t) out.push_back(header(t, 1, 1));
  out.push_back(header(255, 0, 1) + "rocks");
  return out;
}

}  // namespace gtbake::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gtbake;
  if (size < fuzz::kHeader) return 0;
  const auto& names = corpusTypeNames();
  const std::string type =
      data[0] < names.size()
          ? names[data[0]]
          : std::string(reinterpret_cast<const char*>(data) + fuzz::kHeader, size - fuzz::kHeader);
  std::int32_t variant = 0;
  std::uint64_t seed = 0;
  std::memcpy(&variant, data + 1, 4);
  std::memcpy(&seed, data + 5, 8);
  try {
    fuzz::checkScene(makeCorpusScene(type, variant, seed), type, variant);
  } catch (const Error& e) {
    fuzz::requireOneLine(e);
  }
  return 0;
}
