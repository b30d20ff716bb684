// Fuzz target: the environment reader of gtbake lighting (lighting/environment.h, docs/lighting.md
// §2) on arbitrary bytes: decodeEnvironmentExr, then the projection. Anything but a one-line
// gtbake::Error or an SH vector is a bug.
#include "common/error.h"
#include "common/image_io.h"
#include "fuzz_target.h"
#include "lighting/environment.h"

namespace gtbake::fuzz {

std::vector<std::string> seeds() {
  std::vector<std::string> out;
  std::vector<ExrChannel> rgb;
  for (const char* name : {"R", "G", "B"}) {
    std::vector<float> pixels(8 * 4);
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<float>(i) / 8.0f;
    rgb.push_back({name, pixels});
  }
  out.push_back(encodeExr(8, 4, rgb));
  out.push_back(encodeExr(4, 2, {{"Y", std::vector<float>(8, 1.0f)}}));
  return out;
}

}  // namespace gtbake::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gtbake;
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    projectEquirect(decodeEnvironmentExr(bytes, "fuzz.exr"), "fuzz.exr");
  } catch (const Error& e) {
    fuzz::requireOneLine(e);
  }
  return 0;
}
