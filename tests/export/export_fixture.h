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
