// validate-gtso: the shader-exact lookup against the tables' own texels, the fast cone model
// against gtso's, the u fit on synthetic data with a known u, Lagarde's formula by hand, and the
// bad input of a sweep without specular channels.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/math_constants.h"
#include "encode/bc4_layout.h"
#include "encode/encode_command.h"
#include "encode/shipped_volumes.h"
#include "gtso/cone_intersection.h"
#include "gtso/gtso_command.h"
#include "runtime/gtso_runtime.h"
#include "scene/procedural_scenes.h"
#include "scene/scene.h"
#include "support/test_scenes.h"
#include "sweep/sweep_command.h"
#include "texture/bc4_block.h"
#include "texture/bc4_encoder.h"
#include "texture/texture_containers.h"
#include "validate_gtso/cone_u_fit.h"
#include "validate_gtso/gtso_lookup.h"
#include "validate_gtso/specular_methods.h"
#include "validate_gtso/validate_gtso_command.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

// At a texel centre the trilinear filter returns that texel: the float lookup gives the float
// table's value and the BC4 lookup the decoded DDS block's, for texels all over both tables (the
// 4D fold included). The inputs are the texel's physical parameters (gtsoTexelPhysical, the
// bake's inverse axis maps) passed as a runtime would (cos β, cos θo, in float), so a texel's
// coordinate lands near, not exactly on, its centre; the test bounds what that costs.
TEST(ValidateGtso, LookupAtTexelCentresReturnsTheTexels) {
  // Fresh 16^3 / 16^4 tables (gtbake gtso), their volumes by `gtbake encode`.
  const fs::path root =
      fs::temp_directory_path() / ("gtbake_test_validate_lookup_" + std::to_string(::getpid()));
  fs::remove_all(root);
  GtsoOptions bake;
  bake.out = root / "gtso";
  bake.size = 16;
  bake.lobe_cells = 24;
  bake.error_lobes = 16;
  bake.error_seeds = 1;
  bake.progress = false;
  bake.closed_form_lobes = 64;  // the lookups, not the closed form (s3_closed_form_test.cpp)
  runGtso(bake);
  const GtsoInput gtso = readGtsoInput(root / "gtso");
  EncodeOptions encode;
  encode.gtso = root / "gtso";
  encode.out = root / "encode";  // where makeTablesLookups reads them (docs/reproducibility.md)
  encode.layout_lobes = 64;
  encode.progress = false;
  runEncode(encode);
  const ShippedVolumes shipped = readShippedVolumes(encode.out, gtso);
  const TablesLookups lookups = makeTablesLookups(root);
  EXPECT_EQ(lookups.info.layout_3d, layoutSwizzle(shipped.t3.layout));
  EXPECT_EQ(lookups.info.layout_4d, layoutSwizzle(shipped.t4.layout));
  const GtsoTable& t3 = gtso.table3d;
  const GtsoTable& t4 = gtso.table4d;
  // The decoded BC4 texels of a table's chosen layout, back in table order.
  auto decoded = [&](const GtsoTable& t, const ShippedVolume& c) {
    const std::vector<float> d =
        decodeBc4Volume(c.bc4.bytes.data(), c.volume[0], c.volume[1], c.volume[2]);
    GtsoTable index = t;  // permuteToLayout of the texel numbers: texture position -> table index
    for (std::size_t i = 0; i < index.values.size(); ++i) index.values[i] = static_cast<float>(i);
    const std::vector<float> where = permuteToLayout(index, c.layout);
    std::vector<float> out(d.size());
    for (std::size_t k = 0; k < d.size(); ++k) out[static_cast<std::size_t>(where[k])] = d[k];
    return out;
  };
  // R16 / R8: what the texture unit returns for texel i, round(v (2^b - 1)) / (2^b - 1).
  auto quantised = [](const GtsoTable& t, double levels) {
    std::vector<float> q(t.values.size());
    for (std::size_t i = 0; i < q.size(); ++i) {
      const double v = std::clamp(static_cast<double>(t.values[i]), 0.0, 1.0);
      q[i] = static_cast<float>(std::round(v * levels)) / static_cast<float>(levels);
    }
    return q;
  };
  const std::vector<float> bc4_3 = decoded(t3, shipped.t3);
  const std::vector<float> bc4_4 = decoded(t4, shipped.t4);
  const std::vector<float> r16_3 = quantised(t3, 65535.0), r16_4 = quantised(t4, 65535.0);
  const std::vector<float> r8_3 = quantised(t3, 255.0), r8_4 = quantised(t4, 255.0);
  const int size3[3] = {t3.dims[0], t3.dims[1], t3.dims[2]};
  const int size4[4] = {t4.dims[0], t4.dims[1], t4.dims[2], t4.dims[3]};
  const int n = size3[0];
  std::vector<double> errors;   // 3D
  std::vector<double> errors4;  // 4D
  for (int i = 1; i < n - 1; i += 2) {
    for (int j = 1; j < n - 1; j += 2) {
      for (int k = 1; k < n - 1; k += 2) {
        const int idx3[3] = {i, j, k};
        const GtsoPhysical<double> p = gtsoTexelPhysical<double>(3, idx3, size3);
        if (p.alphaV < 0.0 || p.alphaV > kPi / 2) continue;  // continuation texels: A clamped
        const std::size_t at3 = (static_cast<std::size_t>(k) * n + j) * n + i;
        const auto A = static_cast<float>(p.A);
        const auto cb = static_cast<float>(std::cos(p.beta));
        const auto rp = static_cast<float>(p.rp);
        errors.push_back(std::abs(lookups.floats->s3(A, cb, rp) - t3.values[at3]));
        errors.push_back(std::abs(lookups.bc4->s3(A, cb, rp) - bc4_3[at3]));
        errors.push_back(std::abs(lookups.r16->s3(A, cb, rp) - r16_3[at3]));
        errors.push_back(std::abs(lookups.r8->s3(A, cb, rp) - r8_3[at3]));
        for (int l : {1, n / 2, n - 2}) {
          const int idx4[4] = {i, j, k, l};
          const GtsoPhysical<double> q = gtsoTexelPhysical<double>(4, idx4, size4);
          if (q.alphaV < 0.0 || q.alphaV > kPi / 2) continue;
          const std::size_t at4 =
              ((static_cast<std::size_t>(l) * n + k) * n + j) * static_cast<std::size_t>(n) + i;
          const auto A4 = static_cast<float>(q.A);
          const auto cb4 = static_cast<float>(std::cos(q.beta));
          const auto ct4 = static_cast<float>(std::cos(q.thetaO));
          const auto rp4 = static_cast<float>(q.rp);
          errors4.push_back(std::abs(lookups.floats->s4(A4, cb4, rp4, ct4) - t4.values[at4]));
          errors4.push_back(std::abs(lookups.bc4->s4(A4, cb4, rp4, ct4) - bc4_4[at4]));
          errors4.push_back(std::abs(lookups.r16->s4(A4, cb4, rp4, ct4) - r16_4[at4]));
          errors4.push_back(std::abs(lookups.r8->s4(A4, cb4, rp4, ct4) - r8_4[at4]));
        }
      }
    }
  }
  std::sort(errors.begin(), errors.end());
  std::sort(errors4.begin(), errors4.end());
  // 4D: the bulk sits on the texels; a minority does not (the β round trip through cos β for
  // texels of the beta axis), so only the median is checked.
  std::printf("[ info ] 4D |lookup - texel| at %zu texel centres: median %.3g, max %.3g\n",
              errors4.size(), errors4[errors4.size() / 2], errors4.back());
  EXPECT_LT(errors4[errors4.size() / 2], 1e-6);
  const double median = errors[errors.size() / 2];
  const double p95 = errors[errors.size() * 95 / 100];
  const double worst = errors.back();
  std::printf(
      "[ info ] 3D |lookup - texel| at %zu texel centres: median %.3g, 95%% %.3g, max %.3g\n",
      errors.size(), median, p95, worst);
  // 3D: where an axis is steep (the A axis near the step; θo near normal view, refined to
  // λ = 3e-3 rad, where acos of a float cosine resolves θo only to ~6e-8/θo), the float round
  // trip moves a few coordinates off their centres; 95% must sit within 3e-5 of them.
  EXPECT_LT(median, 1e-6);
  EXPECT_LT(p95, 3e-5);

  // The files hold what the layout choice encodes in memory (its blocks, its texels quantised),
  // read back through the texture library's DDS reader.
  GtsoLayouts layouts = chooseLayouts(gtso, 64, nullptr, nullptr, false);
  packLayoutChoice(gtso.table4d, Layout4D::kAtlas, kAtlasMaxExtent, &layouts.t4);  // as encode
  for (const auto& [c, v] :
       {std::pair{&layouts.t3, &shipped.t3}, std::pair{&layouts.t4, &shipped.t4}}) {
    EXPECT_EQ(c->layout.axis[0], v->layout.axis[0]);
    EXPECT_EQ(c->bc4.bytes, v->bc4.bytes);
    EXPECT_EQ(quantizeUnorm(c->texels.data(), c->texels.size(), TexelFormat::kR16), v->r16.bytes);
    EXPECT_EQ(quantizeUnorm(c->texels.data(), c->texels.size(), TexelFormat::kR8), v->r8.bytes);
  }
  EXPECT_EQ(lookups.info.r16_source, "gtso3d_r16.dds, gtso4d_r16.dds");
  EXPECT_EQ(lookups.info.r8_source, "gtso3d_r8.dds, gtso4d_r8.dds");
  std::mt19937 gen(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  float r8_vs_r16 = 0.0f;
  for (int p = 0; p < 2000; ++p) {
    const float A = unit(gen), cb = 2.0f * unit(gen) - 1.0f, rp = unit(gen), ct = unit(gen);
    r8_vs_r16 = std::max(r8_vs_r16,
                         std::abs(lookups.r8->s4(A, cb, rp, ct) - lookups.r16->s4(A, cb, rp, ct)));
  }
  EXPECT_LE(r8_vs_r16, 0.5f / 255.0f + 1e-5f);  // R8 is R16 re-quantised: half an 8-bit step
  // The split lookups (axis warps once, shared by every table read) give the whole lookups' bits,
  // the ends of every input included.
  const GtsoLookup* all[] = {lookups.bc4.get(), lookups.floats.get(), lookups.r16.get(),
                             lookups.r8.get()};
  // ... and the runtime's own lookups on the encoded volumes (the lookups decode every texel
  // once, by the runtime's fetch, and filter the floats): the same bits for every format.
  const std::vector<std::uint64_t> blocks3 = bc4BlockWords(shipped.t3.bc4.bytes),
                                   blocks4 = bc4BlockWords(shipped.t4.bc4.bytes);
  const std::vector<std::uint16_t> words3 = r16Words(shipped.t3.r16.bytes),
                                   words4 = r16Words(shipped.t4.r16.bytes);
  const auto encoded = [](TexelFormat format, const void* texels, const ShippedVolume& v) {
    return GtsoVolume{format, texels, v.volume[0], v.volume[1], v.volume[2]};
  };
  const std::pair<const GtsoLookup*, std::array<GtsoVolume, 2>> runtime[] = {
      {lookups.bc4.get(),
       {encoded(TexelFormat::kBc4, blocks3.data(), shipped.t3),
        encoded(TexelFormat::kBc4, blocks4.data(), shipped.t4)}},
      {lookups.r16.get(),
       {encoded(TexelFormat::kR16, words3.data(), shipped.t3),
        encoded(TexelFormat::kR16, words4.data(), shipped.t4)}},
      {lookups.r8.get(),
       {encoded(TexelFormat::kR8, shipped.t3.r8.bytes.data(), shipped.t3),
        encoded(TexelFormat::kR8, shipped.t4.r8.bytes.data(), shipped.t4)}}};
  const float ends[] = {0.0f, 1.0f};
  for (int p = 0; p < 20000; ++p) {
    float A = unit(gen), cb = 2.0f * unit(gen) - 1.0f, rp = unit(gen), ct = unit(gen);
    if (p % 7 == 0) A = ends[p % 2];
    if (p % 11 == 0) rp = ends[p % 2];
    if (p % 13 == 0) ct = ends[p % 2];
    if (p % 17 == 0) cb = p % 2 == 0 ? -1.0f : 1.0f;
    const GtsoAxisT<float> axes3 = lookups.bc4->axes3(A, cb, rp);
    const GtsoAxisT<float> axes4 = lookups.bc4->axes4(A, cb, rp, ct);
    for (const GtsoLookup* lookup : all) {
      ASSERT_EQ(lookup->s3At(axes3), lookup->s3(A, cb, rp));
      ASSERT_EQ(lookup->s4At(axes4), lookup->s4(A, cb, rp, ct));
    }
    for (const auto& [lookup, v] : runtime) {
      ASSERT_EQ(lookup->s3(A, cb, rp), gtso3DLookup(v[0], size3, A, cb, rp, shipped.t3.layout));
      ASSERT_EQ(lookup->s4(A, cb, rp, ct),
                gtso4DLookup(v[1], size4, A, cb, rp, ct, shipped.t4.layout));
    }
  }
  fs::remove_all(root);
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
// contains it, under the convention the data were made with; it is the SSE's minimum, and the
// table-guided fit of the pipeline agrees with the scanned one.
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
    // The minimum: 1e-4 decades either side the RMSE is not lower (the minimiser reaches 1e-5).
    auto rmse = [&](double u) {
      double sse = 0.0;
      for (const SpecularSample& s : samples) {
        const double e = coneAt(s, u, perceptual) - s.truth;
        sse += e * e;
      }
      return std::sqrt(sse / static_cast<double>(samples.size()));
    };
    EXPECT_LE(fits.all.rmse, rmse(fits.all.u * std::pow(10.0, 1e-4)));
    EXPECT_LE(fits.all.rmse, rmse(fits.all.u * std::pow(10.0, -1e-4)));
    // Guided by the cone SSE table (its grid the scan, the bisections checked at their ends), the
    // fit finds the same minimum and the same interval ends to the bisection's resolution.
    const ConeSseTable table = coneSseTable(samples, std::vector<int>(1, 0), 1, 5);
    const UFits guided = fitConeU(samples, perceptual, &table);
    for (const auto& [a, b] :
         {std::pair{&fits.all, &guided.all}, {&fits.rp_ge_0_3, &guided.rp_ge_0_3}}) {
      EXPECT_NEAR(std::log10(b->u), std::log10(a->u), 1e-5) << perceptual;
      EXPECT_NEAR(std::log10(b->low), std::log10(a->low), 12.0 / 4096.0) << perceptual;
      EXPECT_NEAR(std::log10(b->high), std::log10(a->high), 12.0 / 4096.0) << perceptual;
    }
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
  o.luts = root;  // never read: the sweep is rejected first
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
