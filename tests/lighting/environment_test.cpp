// Environments as L2 SH (docs/lighting.md §2): the exact per-pixel projection of equirectangular
// maps (a constant gives L_0 alone, a clamped cosine lobe its Funk–Hecke closed form), the
// built-in classes' normalisation, and bad input refused in one line.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include "common/error.h"
#include "common/image_io.h"
#include "common/math_constants.h"
#include "lighting/environment.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

// L(direction) at the pixel centres of a width × width/2 map (environment.h's convention).
EquirectMap sampled(int width, const std::function<double(double, double, double)>& radiance) {
  EquirectMap map;
  map.width = width;
  map.height = width / 2;
  for (int j = 0; j < map.height; ++j) {
    const double theta = kPi * (j + 0.5) / map.height;
    for (int i = 0; i < map.width; ++i) {
      const double phi = 2.0 * kPi * (i + 0.5) / map.width - kPi;
      map.radiance.push_back(radiance(std::sin(theta) * std::cos(phi), std::cos(theta),
                                      std::sin(theta) * std::sin(phi)));
    }
  }
  return map;
}

void expectOneLineError(const std::function<void()>& run, const std::string& fragment) {
  try {
    run();
    ADD_FAILURE() << "accepted: " << fragment;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(Environment, ConstantMapGivesOnlyL0) {
  for (int width : {8, 64, 1000}) {
    const ShVector sh =
        projectEquirect(sampled(width, [](double, double, double) { return 3.0; }), "c");
    // ∫ 3 Y_0 dω = 3 · ½√(1/π) · 4π = 6√π.
    EXPECT_NEAR(sh[0], 6.0 * std::sqrt(kPi), 1e-10) << width;  // rounding over 5e5 pixels
    for (int i = 1; i < kShCoefficients; ++i) EXPECT_NEAR(sh[i], 0.0, 1e-10) << width << " " << i;
    // Uniform radiance 3 gives irradiance/π = 3 for every normal.
    EXPECT_NEAR(openIrradiance(sh, 0.6, 0.0, -0.8), 3.0, 1e-10);
  }
}

// max(0, a·ω) projects to Â_l Y_i(a) (Funk–Hecke; Â = π, 2π/3, π/4). The map samples the lobe at
// pixel centres, so the only error is the midpoint rule's across the terminator: O(1/H²).
TEST(Environment, CosineLobeMatchesClosedForm) {
  const double axes[2][3] = {{0.0, 1.0, 0.0}, {1.0, 0.5, -0.3}};
  for (const auto& axis : axes) {
    const double norm = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    const double a[3] = {axis[0] / norm, axis[1] / norm, axis[2] / norm};
    const ShVector sh = projectEquirect(
        sampled(1024, [&](double x, double y,
                          double z) { return std::max(0.0, a[0] * x + a[1] * y + a[2] * z); }),
        "lobe");
    double basis[kShCoefficients];
    shBasis(a[0], a[1], a[2], basis);
    for (int i = 0; i < kShCoefficients; ++i) {
      EXPECT_NEAR(sh[i], clampedCosineBand(shBand(i)) * basis[i], 2e-5) << i;
    }
  }
}

TEST(Environment, BuiltInClassesLightAnOpenFloorAlike) {
  for (const std::string& name : environmentClasses()) {
    const Environment env = builtInEnvironment(name);
    EXPECT_EQ(env.name, name);
    EXPECT_NEAR(openIrradiance(env.sh, 0.0, 1.0, 0.0), 1.0, 1e-12) << name;
  }
  const ShVector uniform = builtInEnvironment("uniform").sh;
  EXPECT_NEAR(uniform[0], 2.0 * std::sqrt(kPi), 1e-12);
  // Overcast: a wall (normal +x) receives less than the floor; horizon: more.
  EXPECT_LT(openIrradiance(builtInEnvironment("overcast").sh, 1, 0, 0), 0.9);
  EXPECT_GT(openIrradiance(builtInEnvironment("horizon").sh, 1, 0, 0), 1.0);
  // The window lights +x faces, not −x ones; the sun (towards +x) too.
  const ShVector window = builtInEnvironment("window").sh;
  EXPECT_GT(openIrradiance(window, 1, 0, 0), 1.5);
  EXPECT_LT(openIrradiance(window, -1, 0, 0), 0.1);
  const ShVector sun = builtInEnvironment("sun-sky").sh;
  EXPECT_GT(openIrradiance(sun, 1, 0, 0), openIrradiance(sun, -1, 0, 0));
  EXPECT_EQ(environmentFromArgument("window").sh, window);
}

TEST(Environment, ReadsRgbExr) {
  const fs::path file =
      fs::temp_directory_path() / ("gtbake_env_" + std::to_string(::getpid()) + ".exr");
  std::vector<ExrChannel> channels;
  for (const char* name : {"R", "G", "B"})
    channels.push_back({name, std::vector<float>(32 * 16, 2.0f)});
  writeExr(file, 32, 16, channels);
  const Environment env = readEnvironment(file);
  fs::remove(file);
  EXPECT_EQ(env.name, file.stem().string());
  // Scaled like the classes: uniform radiance gives G = 1 on every normal.
  EXPECT_NEAR(openIrradiance(env.sh, 0.0, 0.0, 1.0), 1.0, 1e-9);
}

TEST(Environment, BadInputIsOneLine) {
  EquirectMap square = sampled(8, [](double, double, double) { return 1.0; });
  square.width = 4;
  square.height = 4;
  square.radiance.resize(16);
  expectOneLineError([&] { projectEquirect(square, "square"); }, "twice as wide as high");
  for (double bad : {std::nan(""), HUGE_VAL, -1.0}) {
    EquirectMap map = sampled(8, [](double, double, double) { return 1.0; });
    map.radiance[5] = bad;
    expectOneLineError([&] { projectEquirect(map, "bad"); }, "negative or not finite");
  }
  expectOneLineError([] { readEnvironment("/nonexistent/sky.exr"); }, "sky.exr");
  expectOneLineError([] { decodeEnvironmentExr("not an exr", "junk.exr"); }, "junk.exr");
  expectOneLineError(
      [] {
        decodeEnvironmentExr(encodeExr(4, 2, {{"A", std::vector<float>(8, 1.0f)}}), "a.exr");
      },
      "R, G and B channels or a Y channel");
  expectOneLineError([] { builtInEnvironment("dusk"); }, "unknown environment class 'dusk'");
  std::vector<float> values(8, 1.0f);
  values[3] = std::nanf("");
  expectOneLineError(
      [&] {
        decodeEnvironmentExr(encodeExr(4, 2, {{"Y", values}}), "nan.exr");
      },
      "nan.exr: pixel (3, 0) is not finite");
  // A tiny negative value of a lossy encoding is read as 0.
  values[3] = -1e-6f;
  EXPECT_EQ(decodeEnvironmentExr(encodeExr(4, 2, {{"Y", values}}), "neg.exr").radiance[3], 0.0);
}

}  // namespace
}  // namespace gtbake
