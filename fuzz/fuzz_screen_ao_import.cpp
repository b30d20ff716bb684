// Fuzz target: the reader of an engine pass's image (decodeImportedEstimate, `gtbake screen-ao
// --import`, docs/screen_ao.md §8) on arbitrary bytes, against a fixed 8 × 8 G-buffer with half
// its pixels masked. The seeds hold A alone, A with a world-space bent normal and A with a
// view-space one. Anything but a one-line gtbake::Error or an estimate is a bug.
#include "common/error.h"
#include "common/image_io.h"
#include "fuzz_target.h"
#include "screen_ao/screen_ao_import.h"

namespace gtbake::fuzz {

namespace {

constexpr int kSide = 8;
constexpr std::size_t kPixels = kSide * kSide;

SweepImage sweepImage() {
  std::map<std::string, std::vector<float>> channels;
  channels["mask"].resize(kPixels);
  for (std::size_t p = 0; p < kPixels; ++p) channels["mask"][p] = p % 2 == 0 ? 1.0f : 0.0f;
  channels["Z"].assign(kPixels, 2.0f);
  channels["NX"].assign(kPixels, 0.0f);
  channels["NY"].assign(kPixels, 0.0f);
  channels["NZ"].assign(kPixels, 1.0f);
  SweepImage image;
  image.name = "a";
  image.gbuffer = gbufferFromChannels(kSide, kSide, PerspectiveCamera{}, channels, "seed");
  return image;
}

}  // namespace

std::vector<std::string> seeds() {
  std::vector<float> a(kPixels), zero(kPixels, 0.0f), one(kPixels, 1.0f);
  for (std::size_t p = 0; p < kPixels; ++p) a[p] = static_cast<float>(p) / kPixels;
  return {encodeExr(kSide, kSide, {{"A", a}}),
          encodeExr(kSide, kSide, {{"A", a}, {"BNX", zero}, {"BNY", zero}, {"BNZ", one}}),
          encodeExr(kSide, kSide, {{"A", a}, {"VBNX", zero}, {"VBNY", one}, {"VBNZ", zero}})};
}

}  // namespace gtbake::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gtbake;
  static const SweepImage image = fuzz::sweepImage();
  try {
    decodeImportedEstimate(std::string(reinterpret_cast<const char*>(data), size), "fuzz.exr",
                           image);
  } catch (const Error& e) {
    fuzz::requireOneLine(e);
  }
  return 0;
}
