// A small synthetic `gtbake gtso` directory and fit.json for the export tests: smooth tables with
// known values (so tests can compare decoded texels against them), axes using several of the
// vocabulary's quantities (one axis runs from max to min).
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace gtbake::test {

// Table extents of the fixture: 3D 8×8×6; 4D 8×8×4×3 (folded 8×8×12).
inline constexpr int kFixture3D[3] = {8, 8, 6};
inline constexpr int kFixture4D[4] = {8, 8, 4, 3};
inline constexpr double kFixtureU = 0.0125;
inline constexpr double kFixtureCoeffs[6] = {2.0404, -0.3324, 4.7951, -0.6417, 2.7552, 0.6903};
// Closed-form S3 coefficients of the fixture's gtso.json (a cold fit of `gtbake gtso`'s form:
// the warm start of src/gtso/s3_closed_form.cpp), kGtsoS3ClosedFormCoeffs values.
// clang-format off
inline constexpr double kFixtureS3ClosedForm[90] = {
    9.75488264, -3.3189302, -5.4086258, 5.54219672, -5.10556755, -0.989231607, -10.4967237, 10.9599926, -0.252841486, -0.631443479,
    2.19622176, -0.019471876, 3.25174535, -1.06119822, 1.02771828, -3.3431972, -1.13682657, -0.310314097, -1.09337936, -0.119492186,
    3.44109176, -1.56064162, -2.2377054, 0.927638977, -1.09976239, 0.37817493, -3.4783804, 3.42301438, 0.557966003, -0.701816053,
    0.283472897, 0.680386573, 0.744310329, -0.0592264792, -0.40008201, -0.506193609, -1.10519423, -0.0984669146, 0.117260104, 2.86761599,
    -2.85528145, -4.31650337, 67.8226938, 0.867357916, 0.0178802791, -43.8099173, 4.59089268, 4.28756787, -61.6178144, -1.95824495,
    0.615088449, 0.622007007, -0.395059731, 0.37898799, -0.509276148, 0.00545769881, -0.369843704, -0.43780872, -0.0257470419, 2.19508487,
    37.9552625, -2.7299605, 2.13119594, -1.9104191, -0.299448573, -17.2145903, -74.5344546, 3.3376914, 2.82412879, 36.1882954,
    -4.84618248, -8.2231093, 10.6116546, 1.69502707, 1.75196444, -8.23827992, 10.9055298, 5.96062919, 2.71711376, -9.62756796,
    0.288591776, 0.277522305, 2.96195151, 3.92612564, -3.25230289, -3.22887143, -1.23453324, 4.61708739, -5.63397068, 0.609188676,
};
// clang-format on

// The fixture's smooth value at normalised axis positions t (x, y, z[, w]) in [0, 1].
float fixtureValue(double tx, double ty, double tz, double tw);
// All texels of the 3D table / folded 4D table, x fastest.
std::vector<float> fixtureTable3D();
std::vector<float> fixtureTable4D();

// Non-identity texture layouts the exported fixture is forced to (export_fixture_gen, the shader
// test), so the generated header and the executed shaders read permuted volumes: 3D texture
// x = theta_o, y = A, z = r_p (the fixture's 6 r_p texels cannot be in the BC4 block plane); 4D
// x = beta, y = r_p, z = A (the layout export chooses for the real 4D table).
inline const std::vector<int> kFixtureLayout3D = {1, 0, 2};
inline const std::vector<int> kFixtureLayout4D = {1, 2, 0};
// The fixture's 4D table (4D layout: 8x4x8 tiles, 3 theta_o slices) fits a 256-texel fold, so
// the atlas is exercised with this largest extent instead: 2 x 2 tiles, 16x4x16, one tile past
// the last slice (EncodeOptions::atlas_max_extent).
inline constexpr int kFixtureAtlasMaxExtent = 16;

// Writes DIR/gtso/{gtso3d.f32, gtso4d.f32, gtso.json} and DIR/fit.json.
void writeFixture(const std::filesystem::path& dir);

// The fixture's engine profiles (docs/profiles.md): estimator names, their coefficients (the
// fixture's, scaled by 1 + 0.01 (k + 1) for profile k) and their RMSEs.
inline const char* const kFixtureProfiles[2] = {"gtao-runtime", "hbao"};
std::array<double, 6> fixtureProfileCoeffs(int k);
inline constexpr double kFixtureProfilePaperRmse = 0.05, kFixtureProfileHeldOutRmse = 0.03;
// The monotone 2D tables the two fixture profiles ship (docs/profiles.md §8): 4 nodes of A
// (0, 1/3, 2/3, 1) at two albedos each, rising to 1. Two, so that the includes' one lookup reads
// the second (hbao's) at an offset in the arrays that hold both.
inline constexpr double kFixtureTableRho[2][2] = {{0.3, 0.6}, {0.2, 0.8}};
inline constexpr double kFixtureTable[2][2][4] = {{{0.2, 0.4, 0.5, 1.0}, {0.3, 0.6, 0.8, 1.0}},
                                                  {{0.1, 0.3, 0.6, 1.0}, {0.2, 0.5, 0.7, 1.0}}};
inline constexpr double kFixtureTableHeldOutRmse[2] = {0.035, 0.025};
// Profile k's table looked up by hand: linear in A between nodes and in the albedo between the
// rows, both clamped (docs/profiles.md §8).
inline double fixtureTableLookup(int k, double A, double albedo) {
  const auto row = [k, A](int j) {
    const double x = (A < 0.0 ? 0.0 : A > 1.0 ? 1.0 : A) * 3.0;
    const int i = x < 2.0 ? static_cast<int>(x) : 2;
    const double* v = kFixtureTable[k][j];
    return v[i] + (x - i) * (v[i + 1] - v[i]);
  };
  const double* rho = kFixtureTableRho[k];
  const double t = (albedo - rho[0]) / (rho[1] - rho[0]);
  const double s = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
  return row(0) + s * (row(1) - row(0));
}
// Writes DIR/<estimator>/fit.json (a `gtbake fit --estimator` result with its manifest) for
// `estimator` with profile k's values; `claimed` is the estimator its /input names.
void writeProfileFixture(const std::filesystem::path& dir, const std::string& estimator, int k,
                         const std::string& claimed = "");

}  // namespace gtbake::test
