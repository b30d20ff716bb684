// Fuzz target: the reader of a screen-ao set (ScreenEstimateSet, which fit --estimator and
// validate-gtso --estimator use): screen_ao.json and an image's EXR, sealed into a valid set so the
// reader's own checks (not just the manifest's hash) run. The first byte picks the file the rest
// replaces:
//   0 screen_ao.json (beside a valid a.exr)   1 a.exr (beside a valid screen_ao.json)
// Each input is read as both estimators the seed lists, both images, with and without the bent
// normal. Anything but a gtbake::Error is a bug.
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/image_io.h"
#include "fit/screen_estimate.h"
#include "fuzz_target.h"

namespace gtbake::fuzz {

namespace {

constexpr int kSide = 8;
const char* const kEstimators[] = {"gtao-runtime", "hbao"};

// A screen-ao image: mask, and per estimator Â and a unit bent normal (+z), half the pixels masked.
std::string imageExr() {
  const std::size_t n = kSide * kSide;
  std::vector<float> mask(n), a(n), zero(n, 0.0f), one(n, 1.0f);
  for (std::size_t p = 0; p < n; ++p) {
    mask[p] = p % 2 == 0 ? 1.0f : 0.0f;
    a[p] = static_cast<float>(p) / static_cast<float>(n);
  }
  std::vector<ExrChannel> channels = {{"mask", mask}};
  for (const char* e : kEstimators) {
    const std::string name(e);
    channels.push_back({name + ".A", a});
    channels.push_back({name + ".BNX", zero});
    channels.push_back({name + ".BNY", zero});
    channels.push_back({name + ".BNZ", one});
  }
  return encodeExr(kSide, kSide, channels);
}

std::string resultJson() {
  nlohmann::json doc;
  for (const char* e : kEstimators) doc["estimators"][e] = {{"radius", 1.0}};
  doc["images"] = {{{"name", "a"}, {"file", "a.exr"}, {"width", kSide}, {"height", kSide}},
                   {{"name", "b"}, {"file", "a.exr"}, {"width", kSide}, {"height", kSide}}};
  return doc.dump();
}

}  // namespace

std::vector<std::string> seeds() {
  return {std::string(1, '\0') + resultJson(), std::string(1, '\1') + imageExr()};
}

}  // namespace gtbake::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gtbake;
  if (size < 1) return 0;
  static const std::string json = fuzz::resultJson(), exr = fuzz::imageExr();
  const std::string dir = fuzz::scratchDir() + "/screen_ao";
  const std::string doc(reinterpret_cast<const char*>(data) + 1, size - 1);
  const bool fuzz_json = data[0] % 2 == 0;
  fuzz::writeSet(dir, "screen_ao",
                 {{"screen_ao.json", fuzz_json ? doc : json}, {"a.exr", fuzz_json ? exr : doc}});
  for (const char* estimator : fuzz::kEstimators) {
    try {
      const ScreenEstimateSet set(AoInput{estimator, dir});
      for (const char* image : {"a", "b"}) {
        for (const bool with_bent : {false, true}) {
          try {
            set.read(image, fuzz::scratchDir(), with_bent);
          } catch (const Error& e) {
            fuzz::requireOneLine(e);
          }
        }
      }
    } catch (const Error& e) {
      fuzz::requireOneLine(e);
    }
  }
  return 0;
}
