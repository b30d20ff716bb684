// Fuzz target: the JSON readers. The first byte picks one; the rest is the document, sealed into
// a valid output set so the reader's own checks (not just the manifest's hash) are exercised:
//   0 sweep.json (loadSweep, with a valid EXR beside it)   1 gtso.json (readGtsoInput)
//   2 fit.json (readFitInput)                              3 a manifest (readOutputSet)
//   4 sweep.json with G-buffer channels and cameras (screen-ao's readSweepImages)
#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/output_set.h"
#include "fit/fit_set.h"
#include "fit/sweep_data.h"
#include "fuzz_target.h"
#include "gtso/gtso_set.h"
#include "screen_ao/gbuffer.h"

namespace gtbake::fuzz {

namespace {

constexpr int kSide = 32;  // 1024 points: loadSweep's minimum
const double kAlbedos[] = {0.1, 0.3, 0.5, 0.7, 0.9};

// One EXR with every channel loadSweep reads, consistent (G = A + ρ P1), and gtso tables.
void writeFixtures(const std::string& dir) {
  static bool done = false;
  if (done) return;
  done = true;
  for (const char* sub : {"/sweep", "/gtso", "/fit", "/set"}) ensureDirectory(dir + sub);
  const std::size_t n = kSide * kSide;
  std::vector<float> a(n), p1(n), mask(n, 1.0f);
  for (std::size_t i = 0; i < n; ++i) {
    a[i] = 0.2f + 0.6f * static_cast<float>(i) / static_cast<float>(n);
    p1[i] = a[i] * (1.0f - a[i]);
  }
  std::vector<ExrChannel> channels = {{"A", a},    {"P1", p1},    {"H0.A", a},   {"H0.P1", p1},
                                      {"H1.A", a}, {"H1.P1", p1}, {"mask", mask}};
  for (double rho : kAlbedos) {
    std::vector<float> g(n);
    for (std::size_t i = 0; i < n; ++i) g[i] = static_cast<float>(a[i] + rho * p1[i]);
    channels.push_back({albedoChannel(rho), g});
  }
  for (const char* scene : {"a", "b"}) {
    writeFileAtomically(dir + "/sweep/" + scene + ".exr",
                        encodeExr(kSide, kSide, channels,
                                  {{"gtbake.spp", "2"},
                                   {"gtbake.bounces", "1"},
                                   {"gtbake.seed", "1"},
                                   {"gtbake.scene", std::string(scene) + ".gltf"}}));
  }
  // The G-buffer sweep: a plane facing the camera at depth 2 (Z, N, BN, A_R1 beside A and mask).
  ensureDirectory(dir + "/gbuffer");
  std::vector<ExrChannel> gbuffer = {{"A", a},
                                     {"mask", mask},
                                     {"A_R1", a},
                                     {"Z", std::vector<float>(n, 2.0f)},
                                     {"NX", std::vector<float>(n, 0.0f)},
                                     {"NY", std::vector<float>(n, 0.0f)},
                                     {"NZ", std::vector<float>(n, 1.0f)},
                                     {"BNX", std::vector<float>(n, 0.0f)},
                                     {"BNY", std::vector<float>(n, 0.0f)},
                                     {"BNZ", std::vector<float>(n, 1.0f)}};
  writeFileAtomically(dir + "/gbuffer/a.exr", encodeExr(kSide, kSide, gbuffer));
  writeFileAtomically(dir + "/gtso/t3.f32", std::string(4 * 4 * 4 * 4, '\0'));
  writeFileAtomically(dir + "/gtso/t4.f32", std::string(4 * 4 * 4 * 4 * 4, '\0'));
}

nlohmann::json sweepJson() {
  nlohmann::json doc;
  doc["settings"] = {{"spp", 2},     {"width", kSide}, {"height", kSide},
                     {"bounces", 1}, {"seed", 1},      {"albedos", {0.1, 0.3, 0.5, 0.7, 0.9}}};
  for (const char* scene : {"a", "b"}) {
    doc["views"].push_back({{"name", scene},
                            {"file", std::string(scene) + ".exr"},
                            {"gltf", std::string(scene) + ".gltf"},
                            {"width", kSide},
                            {"height", kSide},
                            {"unmasked_pixels", kSide * kSide}});
  }
  return doc;
}

nlohmann::json gbufferJson() {
  nlohmann::json doc;
  doc["gtbake_version"] = "0";
  doc["views"].push_back({{"name", "a"},
                          {"file", "a.exr"},
                          {"width", kSide},
                          {"height", kSide},
                          {"camera",
                           {{"model", "perspective"},
                            {"position", {0.0, 0.0, 0.0}},
                            {"right", {1.0, 0.0, 0.0}},
                            {"up", {0.0, 1.0, 0.0}},
                            {"backward", {0.0, 0.0, 1.0}},
                            {"yfov", 0.8}}}});
  return doc;
}

nlohmann::json gtsoJson() {
  auto axis = [](const char* name, const char* quantity) {
    return nlohmann::json{{"axis", name}, {"quantity", quantity}, {"min", 0.0}, {"max", 1.0}};
  };
  nlohmann::json doc;
  doc["tables"]["3d"] = {{"file", "t3.f32"},
                         {"dims", {4, 4, 4}},
                         {"axes", {axis("x", "A"), axis("y", "beta"), axis("z", "r_p")}}};
  doc["tables"]["4d"] = {
      {"file", "t4.f32"},
      {"dims", {4, 4, 4, 4}},
      {"axes", {axis("x", "A"), axis("y", "beta"), axis("z", "r_p"), axis("w", "theta_o")}}};
  doc["cone"] = {{"u", 0.2}, {"u_se", 0.01}};
  return doc;
}

nlohmann::json fitJson() {
  nlohmann::json doc;
  for (const char* c : {"a1", "a0", "b1", "b0", "c1", "c0"}) {
    doc["linear"][c] = 1.0;
    doc["linear_se"][c] = 0.1;
  }
  return doc;
}

}  // namespace

std::vector<std::string> seeds() {
  const std::string manifest =
      R"({"command":"x","gtbake_version":"0","settings":{},"files":[{"name":"a","size":1,)"
      R"("sha256":"ca978112ca1bbdcafac231b39a23dc4da786eff8147c4e72b9807785afee48bb"}]})";
  return {std::string(1, '\0') + sweepJson().dump(), std::string(1, '\1') + gtsoJson().dump(),
          std::string(1, '\2') + fitJson().dump(), std::string(1, '\3') + manifest,
          std::string(1, '\4') + gbufferJson().dump()};
}

}  // namespace gtbake::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gtbake;
  if (size < 1) return 0;
  const std::string dir = fuzz::scratchDir();
  fuzz::writeFixtures(dir);
  const std::string_view doc(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    switch (data[0] % 5) {
      case 0:
        writeFileAtomically(dir + "/sweep/sweep.json", doc);
        sealOutputSet(dir + "/sweep", "sweep", {"sweep.json", "a.exr", "b.exr"});
        loadSweep(dir + "/sweep");
        break;
      case 1:
        writeFileAtomically(dir + "/gtso/gtso.json", doc);
        sealOutputSet(dir + "/gtso", "gtso", {"gtso.json", "t3.f32", "t4.f32"});
        readGtsoInput(dir + "/gtso");
        break;
      case 2:
        writeFileAtomically(dir + "/fit/fit.json", doc);
        sealOutputSet(dir + "/fit", "fit", {"fit.json"});
        readFitInput(dir + "/fit/fit.json");
        break;
      case 4:
        writeFileAtomically(dir + "/gbuffer/sweep.json", doc);
        sealOutputSet(dir + "/gbuffer", "sweep", {"sweep.json", "a.exr"});
        readSweepImages(dir + "/gbuffer");
        break;
      default:
        writeFileAtomically(dir + "/set/x.manifest.json", doc);
        writeFileAtomically(dir + "/set/a", "a");
        verifyOutputSet(readOutputSet(dir + "/set", "x"));
        break;
    }
  } catch (const Error&) {
  }
  return 0;
}
