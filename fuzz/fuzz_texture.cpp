// Fuzz target: parseDds and parseKtx2 on arbitrary bytes (the texture library's volume readers,
// which validate-gtso and export use on encode's files). Anything but a gtbake::Error or a volume
// whose payload matches its extent is a bug.
#include <cstdlib>

#include "common/error.h"
#include "fuzz_target.h"
#include "texture/texture_containers.h"

namespace gtbake::fuzz {

std::vector<std::string> seeds() {
  std::vector<std::uint8_t> bc4(2 * 2 * 3 * 8), r16(8 * 8 * 3 * 2);
  for (std::size_t i = 0; i < bc4.size(); ++i) bc4[i] = static_cast<std::uint8_t>(i * 37);
  for (std::size_t i = 0; i < r16.size(); ++i) r16[i] = static_cast<std::uint8_t>(i * 11);
  const VolumeImage a{8, 8, 3, &bc4, TexelFormat::kBc4}, b{8, 8, 3, &r16, TexelFormat::kR16};
  return {makeDds(a), makeDds(b), makeKtx2(a, "fuzz"), makeKtx2(b, "fuzz")};
}

}  // namespace gtbake::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gtbake;
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  for (bool ktx2 : {false, true}) {
    try {
      const VolumeData v = ktx2 ? parseKtx2(bytes, "fuzz.ktx2") : parseDds(bytes, "fuzz.dds");
      if (v.width <= 0 || v.height <= 0 || v.depth <= 0 || v.bytes.empty()) std::abort();
    } catch (const Error&) {
    }
  }
  return 0;
}
