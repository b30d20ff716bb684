// Fixtures shared by the reliability tests (docs/limits.md): EXPECT_ERROR, a tiny two-scene
// sweep and a tiny gtso + fit.json that export reads.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "common/error.h"
#include "common/output_set.h"
#include "encode/encode_command.h"
#include "export/export_command.h"
#include "gtso/gtso_command.h"
#include "reliability_util.h"
#include "scene/procedural_scenes.h"
#include "scene/scene.h"
#include "support/test_scenes.h"
#include "sweep/sweep_command.h"

namespace gtbake::test {

namespace fs = std::filesystem;
using nlohmann::json;

// The one-line gtbake::Error `f` throws ("" if none).
inline std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    return message;
  }
  return "";
}

// Two tiny scenes every pixel of which sees geometry: a closed box (A = 0 everywhere) and a
// spherical cavity (A from 0 to 1, so the sweep can also be fitted).
struct SweepFixture {
  TempDir root{"sweep_fixture"};
  fs::path scenes = root.path() / "scenes";
  SweepFixture() {
    Scene a = makeClosedBoxScene();
    writeGltfScene(scenes / "box_a.gltf", a);
    writeGltfScene(scenes / "box_b.gltf", makeSphericalCavityScene(1.0, 0.7));
  }
  SweepOptions options(const fs::path& out, std::uint64_t seed = 1, int side = 40) const {
    SweepOptions o;
    o.scenes = {scenes};
    o.out = out;
    o.spp = 2;
    o.width = o.height = side;
    o.bounces = 1;
    o.seed = seed;
    o.threads = 1;
    o.progress = false;
    return o;
  }
};

struct ExportFixture {
  TempDir root{"export_fixture"};
  fs::path gtso = root.path() / "gtso";
  fs::path fit = root.path() / "fit" / "fit.json";
  ExportFixture() {
    GtsoOptions g;
    g.out = gtso;
    g.size = 4;
    g.lobe_cells = 8;
    g.error_lobes = 16;
    g.error_seeds = 1;
    g.progress = false;
    g.threads = 1;
    g.closed_form_lobes = 64;  // the fit's plumbing, not its accuracy (s3_closed_form_test.cpp)
    runGtso(g);
    // fit.json as `gtbake fit` writes it (the fields export reads), sealed as its set.
    json doc;
    const char* names[6] = {"a1", "a0", "b1", "b0", "c1", "c0"};
    for (int i = 0; i < 6; ++i) {
      doc["linear"][names[i]] = 1.0 + i;
      doc["linear_se"][names[i]] = 0.01;
    }
    fs::create_directories(fit.parent_path());
    spit(fit, doc.dump(2));
    sealOutputSet(fit.parent_path(), "fit", {"fit.json"});
  }
  ExportOptions options(const fs::path& out) const {
    ExportOptions e;
    e.fit = fit;
    e.gtso = gtso;
    e.out = out;
    return e;
  }
  // The volumes export reads (`gtbake encode` into the same directory).
  void encode(const fs::path& out) const {
    EncodeOptions e;
    e.gtso = gtso;
    e.out = out;
    e.progress = false;
    e.threads = 1;
    e.layout_lobes = 16;
    runEncode(e);
  }
};

}  // namespace gtbake::test

#define EXPECT_ERROR(statement, fragment)                                         \
  do {                                                                            \
    const std::string message_ = ::gtbake::test::errorOf([&] { statement; });     \
    EXPECT_NE(message_.find(fragment), std::string::npos) << "got: " << message_; \
  } while (0)
