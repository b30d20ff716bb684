// validate-gtso: the shader-exact lookup against the tables' own texels, the fast cone model
// against gtso's, the u fit on synthetic data with a known u, Lagarde's formula by hand, and the
// bad input of a sweep without specular channels.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <random>

#include "common/atomic_file.h"
#include "common/error.h"
#include "export/bc4_encoder.h"
#include "export/export_inputs.h"
#include "gtso/cone_intersection.h"
#include "scene/procedural_scenes.h"
#include "scene/scene.h"
#include "sweep/sweep_command.h"
#include "validate_gtso/cone_u_fit.h"
#include "validate_gtso/gtso_lookup.h"
#include "validate_gtso/specular_methods.h"
#include "validate_gtso/validate_gtso_command.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

const fs::path kLuts = fs::path(GTBAKE_SOURCE_DIR) / "luts";
constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kDdsHeader = 148;  // "DDS " + DDS_HEADER + DDS_HEADER_DXT10

std::vector<float> ddsTexels(const fs::path& path, const std::array<int, 3>& v) {
  const std::string bytes = readFile(path);
  return decodeBc4Volume(reinterpret_cast<const std::uint8_t*>(bytes.data()) + kDdsHeader, v[0],
                         v[1], v[2]);
}

// At a texel centre the trilinear filter returns that texel: the float lookup gives the float
// table's value and the BC4 lookup the decoded DDS block's, for texels all over both tables (the
// 4D fold included), through gtso.json's axis quantities. The inputs are rebuilt from the texel's
// axis values in float (√, cos, acos round trips), so a texel's coordinate lands within ~1e-6 of
// its centre, and its neighbours weigh in by ≤ 1e-5 of their difference.
TEST(ValidateGtso, LookupAtTexelCentresReturnsTheTexels) {
  const TablesLookups lookups = makeTablesLookups(kLuts, false, false);
  const GtsoInput gtso = readGtsoInput(kLuts / "gtso");
  const GtsoTable& t3 = gtso.table3d;
  const GtsoTable& t4 = gtso.table4d;
  ASSERT_EQ(t3.axes[0].quantity, "cos_beta");
  ASSERT_EQ(t3.axes[1].quantity, "r_p");
  ASSERT_EQ(t3.axes[2].quantity, "A");
  ASSERT_EQ(t4.axes[0].quantity, "r_p");
  ASSERT_EQ(t4.axes[1].quantity, "theta_o");
  ASSERT_EQ(t4.axes[2].quantity, "cos_alpha_v");
  ASSERT_EQ(t4.axes[3].quantity, "cos_beta");
  const std::vector<float> bc4_3 = ddsTexels(kLuts / "gtso3d.dds", t3.volume);
  const std::vector<float> bc4_4 = ddsTexels(kLuts / "gtso4d.dds", t4.volume);
  auto at = [](const GtsoAxis& a, int i, int n) { return a.min + (a.max - a.min) * i / (n - 1); };
  const int n = t3.dims[0];
  double worst = 0.0;
  for (int i = 0; i < n; i += 5) {
    for (int j = 0; j < n; j += 3) {
      for (int k = 0; k < n; k += 2) {
        const float cos_beta = static_cast<float>(at(t3.axes[0], i, n));
        const float rp = static_cast<float>(at(t3.axes[1], j, n));
        const float A = static_cast<float>(at(t3.axes[2], k, n));
        const std::size_t idx = (static_cast<std::size_t>(k) * n + j) * n + i;
        const double e1 = std::abs(lookups.floats->s3(A, cos_beta, rp) - t3.values[idx]);
        const double e2 = std::abs(lookups.bc4->s3(A, cos_beta, rp) - bc4_3[idx]);
        worst = std::max({worst, e1, e2});
        ASSERT_LT(e1, 1e-5) << i << " " << j << " " << k;
        ASSERT_LT(e2, 1e-5) << i << " " << j << " " << k;
        for (int l : {0, 7, 16, 30, 31}) {
          const double theta = at(t4.axes[1], j, n);
          const double cos_av = at(t4.axes[2], k, n);
          const float A4 = static_cast<float>(1.0 - cos_av * cos_av);
          const float cb = static_cast<float>(at(t4.axes[3], l, n));
          const float ct = static_cast<float>(std::cos(theta));
          const float r4 = static_cast<float>(at(t4.axes[0], i, n));
          const std::size_t id4 =
              ((static_cast<std::size_t>(l) * n + k) * n + j) * static_cast<std::size_t>(n) + i;
          const double f1 = std::abs(lookups.floats->s4(A4, cb, r4, ct) - t4.values[id4]);
          const double f2 = std::abs(lookups.bc4->s4(A4, cb, r4, ct) - bc4_4[id4]);
          worst = std::max({worst, f1, f2});
          ASSERT_LT(f1, 1e-4) << i << " " << j << " " << k << " " << l;
          ASSERT_LT(f2, 1e-4) << i << " " << j << " " << k << " " << l;
        }
      }
    }
  }
  std::printf("[ info ] largest |lookup - texel| at texel centres: %.3g\n", worst);
}

// The cone model from precomputed trig gives gtso::coneSpecularOcclusion's bits.
TEST(ValidateGtso, FastConeEqualsGtsoCone) {
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int t = 0; t < 20000; ++t) {
    SpecularSample s;
    s.A = static_cast<float>(unit(gen));
    s.r_p = static_cast<float>(unit(gen));
    s.alpha_v = std::acos(std::sqrt(1.0 - static_cast<double>(s.A)));
    s.beta = kPi * unit(gen);
    s.cos_av = std::cos(s.alpha_v);
    s.sin_av = std::sin(s.alpha_v);
    s.cos_b = std::cos(s.beta);
    s.sin_b = std::sin(s.beta);
    const double u = std::pow(10.0, -6.0 * unit(gen));
    const double w = static_cast<double>(s.r_p) * s.r_p;
    ASSERT_EQ(coneAt(s, u, false),
              gtso::coneSpecularOcclusion(s.alpha_v, gtso::specularConeAperture(u, w), s.beta));
  }
}

// Synthetic truth S = S_cone(u = 0.02) plus zero-mean noise: the fit recovers u and its interval
// contains it, under the convention the data were made with.
TEST(ValidateGtso, FitRecoversAKnownU) {
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.02);
  const double u_true = 0.02;
  const float roughness[] = {0.1f, 0.25f, 0.4f, 0.6f, 0.8f};
  for (bool perceptual : {false, true}) {
    std::vector<SpecularSample> samples;
    for (int p = 0; p < 4000; ++p) {
      const double A = unit(gen);
      const double beta = 0.5 * kPi * unit(gen);
      for (int j = 0; j < 5; ++j) {
        SpecularSample s;
        s.roughness = j;
        s.r_p = roughness[j];
        s.A = static_cast<float>(A);
        s.alpha_v = std::acos(std::sqrt(1.0 - static_cast<double>(s.A)));
        s.beta = beta;
        s.cos_av = std::cos(s.alpha_v);
        s.sin_av = std::sin(s.alpha_v);
        s.cos_b = std::cos(s.beta);
        s.sin_b = std::sin(s.beta);
        s.truth = coneAt(s, u_true, perceptual) + noise(gen);
        samples.push_back(s);
      }
    }
    const UFits fits = fitConeU(samples, perceptual);
    EXPECT_NEAR(std::log10(fits.all.u), std::log10(u_true), 0.05) << perceptual;
    EXPECT_LE(fits.all.low, u_true);
    EXPECT_GE(fits.all.high, u_true);
    EXPECT_LT(fits.all.rmse, 0.021);  // the noise's 0.02 plus nothing systematic
    EXPECT_NEAR(std::log10(fits.rp_ge_0_3.u), std::log10(u_true), 0.05) << perceptual;
  }
}

// saturate(pow(n·v + A, exp2(−16 r − 1)) − 1 + A) with r = r_p², by hand.
TEST(ValidateGtso, LagardeByHand) {
  // n·v = 0.5, A = 0.5, r_p = 0.5: pow(1, ·) − 1 + 0.5 = 0.5.
  EXPECT_NEAR(lagarde(0.5f, 0.5f, 0.5f), 0.5f, 1e-6f);
  // n·v = 0.2, A = 0.3, r = 0.1: 0.5^(2^−2.6) − 0.7 = 0.5^0.164938 − 0.7 = 0.191967 (in double).
  EXPECT_NEAR(lagarde(0.2f, 0.3f, static_cast<float>(std::sqrt(0.1))),
              std::pow(0.5, std::exp2(-2.6)) - 0.7, 2e-6);
  EXPECT_EQ(lagarde(0.1f, 0.0f, 0.5f), 0.0f);  // saturate below
  EXPECT_EQ(lagarde(1.0f, 1.0f, 0.2f), 1.0f);
}

// A sweep traced with --specular-roughness none: a one-line error naming the flag, nothing written.
TEST(ValidateGtso, SweepWithoutSpecularChannelsIsOneLineError) {
  const fs::path root =
      fs::temp_directory_path() / ("gtbake_test_validate_gtso_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "scenes");
  writeGltfScene(root / "scenes" / "plane.gltf", makeOpenPlaneScene());
  SweepOptions sweep;
  sweep.scenes = {root / "scenes" / "plane.gltf"};
  sweep.out = root / "sweep";
  sweep.spp = 8;
  sweep.width = 8;
  sweep.height = 8;
  sweep.specular_roughness = {};
  sweep.progress = false;
  runSweep(sweep);
  ValidateGtsoOptions o;
  o.sweep = sweep.out;
  o.luts = kLuts;
  o.out = root / "out";
  o.progress = false;
  try {
    runValidateGtso(o);
    ADD_FAILURE() << "accepted a sweep without specular channels";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("--specular-roughness"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_FALSE(fs::exists(o.out));
  fs::remove_all(root);
}

}  // namespace
}  // namespace gtbake
