// Fuzz target: decodeExr on arbitrary bytes (the sweep EXR reader), with and without a size
// expectation. Anything but a gtbake::Error or an image is a bug.
#include "common/error.h"
#include "common/image_io.h"
#include "fuzz_target.h"

namespace gtbake::fuzz {

std::vector<std::string> seeds() {
  std::vector<ExrChannel> channels;
  for (const char* name : {"A", "P1", "mask"}) {
    std::vector<float> pixels(8 * 6);
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<float>(i) / 48.0f;
    channels.push_back({name, pixels});
  }
  return {encodeExr(8, 6, channels, {{"gtbake.spp", "2"}, {"gtbake.scene", "box.gltf"}})};
}

}  // namespace gtbake::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gtbake;
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    decodeExr(bytes, "fuzz.exr", (size % 2) ? ExrExpect{8, 6, "fuzz"} : ExrExpect{});
  } catch (const Error&) {
  }
  return 0;
}
