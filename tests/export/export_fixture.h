// A small synthetic `gtbake gtso` directory and fit.json for the export tests: smooth tables with
// known values (so tests can compare decoded texels against them), axes using several of the
// vocabulary's quantities (one axis runs from max to min).
#pragma once

#include <filesystem>
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
    9.81482486, -3.92362681, -5.13073714, 5.90935517, -4.68305192, -1.27630897, -9.83895034, 10.4388245, -0.732047768, -0.585247071,
    2.19586035, -0.0770415588, 3.19406587, -0.963712159, 1.00141324, -3.38376903, -1.1264857, -0.288140146, -1.00450214, -0.106302074,
    3.3032664, -1.71258716, -2.0626722, 1.18262804, -1.26168631, 0.284408508, -3.3498033, 3.60336777, 0.381230947, -0.618479216,
    0.253529955, 0.755004783, 0.707819713, -0.10009983, -0.426400671, -0.443885305, -0.850880694, -0.0717574958, -0.145074775, 2.65115967,
    23.4366235, 0.156535093, 40.8942415, -5.19325562, 0.785530459, -35.6567749, -52.6197263, -1.01920273, -29.0995225, 29.0588138,
    0.626534189, 0.772230987, -0.588091201, 0.438560212, -0.695835177, 0.167082284, -0.0501806373, -0.102122921, -0.576876973, 1.74640205,
    35.3533039, -1.19835349, 12.9774923, 0.178459336, -0.603181938, -25.0646921, -71.0616001, 1.94930347, -8.67040499, 35.3993014,
    -4.09341532, -7.95217711, 9.96998482, -0.451230431, 2.7988398, -8.04207605, 9.12630741, 4.64305549, 5.43034853, -8.56954146,
    -0.0155612677, 0.0546721253, 3.67685783, 3.83927178, -3.1366563, -3.56297942, -0.490121926, 4.75172269, -6.20485497, 0.146016191,
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

// Writes DIR/gtso/{gtso3d.f32, gtso4d.f32, gtso.json} and DIR/fit.json.
void writeFixture(const std::filesystem::path& dir);

}  // namespace gtbake::test
