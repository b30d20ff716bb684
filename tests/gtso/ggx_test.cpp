// GGX distribution and visible-normal sampler: normalisation, pdf, inverse, histogram.
#include <gtest/gtest.h>

#include <cmath>

#include "common/math_constants.h"
#include "common/rng.h"
#include "gtso/ggx.h"

namespace gtbake::gtso {
namespace {

// Midpoint rule over the sphere in (cos theta, phi): dw = dcos dphi.
template <typename F>
double integrateSphere(F&& f, int n) {
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double z = -1.0 + 2.0 * (i + 0.5) / n;
    const double r = std::sqrt(1.0 - z * z);
    for (int j = 0; j < 2 * n; ++j) {
      const double phi = kPi * (j + 0.5) / n;
      sum += f(Vec3{r * std::cos(phi), r * std::sin(phi), z});
    }
  }
  return sum * (2.0 / n) * (kPi / n);
}

TEST(Ggx, ProjectedNdfIntegratesToOne) {
  for (double alpha : {0.2, 0.5, 1.0}) {
    const GgxDistribution ggx(alpha);
    const double integral =
        integrateSphere([&](Vec3 w) { return ggx.D(w) * std::max(0.0, w.z); }, 800);
    EXPECT_NEAR(integral, 1.0, 2e-3) << "alpha " << alpha;
  }
}

TEST(Ggx, VisibleNormalPdfIntegratesToOne) {
  for (double alpha : {0.3, 0.8}) {
    const GgxDistribution ggx(alpha);
    for (double cosO : {1.0, 0.6, 0.2}) {
      const Vec3 wo = {std::sqrt(1.0 - cosO * cosO), 0.0, cosO};
      EXPECT_NEAR(integrateSphere([&](Vec3 wm) { return ggx.pdfWm(wo, wm); }, 800), 1.0, 3e-3);
      EXPECT_NEAR(integrateSphere([&](Vec3 wi) { return ggx.pdfWi(wo, wi); }, 800), 1.0, 3e-3);
    }
  }
}

TEST(Ggx, InverseUndoesSample) {
  const CounterRng rng(7, 1);
  for (double alpha : {0.01, 0.3, 1.0}) {
    const GgxDistribution ggx(alpha);
    for (double cosO : {1.0, 0.5, 0.05}) {
      const Vec3 wo = {std::sqrt(1.0 - cosO * cosO), 0.0, cosO};
      for (int n = 0; n < 200; ++n) {
        const auto u = rng.uniform4(n, 0);
        const Point2 p = {0.02 + 0.96 * u[0], 0.02 + 0.96 * u[1]};
        const Point2 q = ggx.invertWm(wo, ggx.sampleWm(wo, p));
        EXPECT_NEAR(q.x, p.x, 1e-7);
        EXPECT_NEAR(q.y, p.y, 1e-7);
      }
    }
  }
}

TEST(Ggx, ConcentricMapInverse) {
  for (double x : {0.1, 0.3, 0.5, 0.77, 0.9})
    for (double y : {0.05, 0.45, 0.62, 0.99}) {
      const Point2 q = invertUniformDiskConcentric(sampleUniformDiskConcentric({x, y}));
      EXPECT_NEAR(q.x, x, 1e-12);
      EXPECT_NEAR(q.y, y, 1e-12);
    }
}

// Histogram of sampled wi over (cos theta, phi) bins against the pdf integrated over each bin.
TEST(Ggx, SampleHistogramMatchesPdf) {
  const GgxDistribution ggx(0.4);
  const Vec3 wo = {0.6, 0.0, 0.8};
  constexpr int kBins = 8, kSamples = 400000;
  std::vector<double> hist(kBins * kBins, 0.0), expect(kBins * kBins, 0.0);
  const CounterRng rng(3, 2);
  for (int n = 0; n < kSamples; ++n) {
    const auto u = rng.uniform4(n, 0);
    const Vec3 wi = ggx.sampleWi(wo, {u[0], u[1]});
    const int bz = std::min(kBins - 1, static_cast<int>((wi.z + 1.0) / 2.0 * kBins));
    double phi = std::atan2(wi.y, wi.x);
    if (phi < 0) phi += 2 * kPi;
    const int bp = std::min(kBins - 1, static_cast<int>(phi / (2 * kPi) * kBins));
    hist[bz * kBins + bp] += 1.0 / kSamples;
  }
  constexpr int kSub = 60;
  for (int bz = 0; bz < kBins; ++bz)
    for (int bp = 0; bp < kBins; ++bp)
      for (int i = 0; i < kSub; ++i)
        for (int j = 0; j < kSub; ++j) {
          const double z = -1.0 + 2.0 * (bz + (i + 0.5) / kSub) / kBins;
          const double phi = 2 * kPi * (bp + (j + 0.5) / kSub) / kBins;
          const double r = std::sqrt(1 - z * z);
          expect[bz * kBins + bp] += ggx.pdfWi(wo, {r * std::cos(phi), r * std::sin(phi), z}) *
                                     (2.0 / kBins / kSub) * (2 * kPi / kBins / kSub);
        }
  for (int b = 0; b < kBins * kBins; ++b) {
    const double se = std::sqrt(std::max(expect[b], 1e-6) / kSamples);
    EXPECT_NEAR(hist[b], expect[b], 5.0 * se + 2e-4) << "bin " << b;
  }
}

// The estimator weight is fr cos / pdf.
TEST(Ggx, WeightIsBrdfCosineOverPdf) {
  const GgxDistribution ggx(0.5);
  const Vec3 wo = {0.5, 0.0, std::sqrt(0.75)};
  const CounterRng rng(5, 3);
  for (int n = 0; n < 100; ++n) {
    const auto u = rng.uniform4(n, 0);
    const Vec3 wi = ggx.sampleWi(wo, {u[0], u[1]});
    if (wi.z <= 1e-3) continue;
    EXPECT_NEAR(ggx.weight(wo, wi), ggx.f(wo, wi) * wi.z / ggx.pdfWi(wo, wi), 1e-9);
  }
}

}  // namespace
}  // namespace gtbake::gtso
