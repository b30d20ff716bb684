#include "export_fixture.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/output_set.h"
#include "runtime/gtso_runtime.h"

namespace gtbake::test {

float fixtureValue(double tx, double ty, double tz, double tw) {
  return static_cast<float>(0.5 + 0.47 * std::sin(1.3 * tx + 2.1 * ty * tz + 0.7 * tw) *
                                      std::cos(0.9 * tz - 0.4 * tw));
}

std::vector<float> fixtureTable3D() {
  const int* n = kFixture3D;
  std::vector<float> v;
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x)
        v.push_back(fixtureValue(x / (n[0] - 1.0), y / (n[1] - 1.0), z / (n[2] - 1.0), 0.0));
  return v;
}

std::vector<float> fixtureTable4D() {
  const int* n = kFixture4D;
  std::vector<float> v;
  for (int w = 0; w < n[3]; ++w)
    for (int z = 0; z < n[2]; ++z)
      for (int y = 0; y < n[1]; ++y)
        for (int x = 0; x < n[0]; ++x)
          v.push_back(
              fixtureValue(x / (n[0] - 1.0), y / (n[1] - 1.0), z / (n[2] - 1.0), w / (n[3] - 1.0)));
  return v;
}

namespace {

void writeFloats(const std::filesystem::path& path, const std::vector<float>& v) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
  out.close();
}

nlohmann::json axes(const gtbake::GtsoAxisInfo* const* info, int rank) {
  static const char* names[4] = {"x", "y", "z", "w"};
  nlohmann::json a = nlohmann::json::array();
  for (int i = 0; i < rank; ++i) a.push_back({{"axis", names[i]}, {"quantity", info[i]->quantity}});
  return a;
}

}  // namespace

void writeFixture(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir / "gtso");
  writeFloats(dir / "gtso" / "gtso3d.f32", fixtureTable3D());
  writeFloats(dir / "gtso" / "gtso4d.f32", fixtureTable4D());
  nlohmann::json g;
  g["version"] = "fixture";
  g["size"] = 8;
  g["roughness_convention"] = "r_p, alpha = r_p^2";
  g["texel_rule"] = "texel i at the inverse axis map of i/(N-1)";
  for (const GtsoAxisConstant& c : kGtsoAxisConstants) g["axis_constants"][c.key] = c.value;
  g["tables"]["3d"] = {{"file", "gtso3d.f32"},
                       {"dims", {kFixture3D[0], kFixture3D[1], kFixture3D[2]}},
                       {"axes", axes(kGtso3DAxisInfo, 3)},
                       {"lobe_grid_rectangles", 64},
                       {"max_abs_error_vs_reference", 1e-4}};
  g["tables"]["4d"] = {{"file", "gtso4d.f32"},
                       {"dims", {kFixture4D[0], kFixture4D[1], kFixture4D[2], kFixture4D[3]}},
                       {"axes", axes(kGtso4DAxisInfo, 4)},
                       {"folded", {kFixture4D[0], kFixture4D[1], kFixture4D[2] * kFixture4D[3]}},
                       {"lobe_grid_rectangles", 64},
                       {"max_abs_error_vs_reference", 1e-4}};
  g["cone"] = {{"u", kFixtureU},
               {"u_se", 0.0005},
               {"convention", "cos(alpha_s) = u^(alpha^2/2)"},
               {"errors", {{"fitted", {{"rmse", 0.01}, {"max_abs", 0.05}}}}}};
  g["closed_form"] = {{"coefficients", std::vector<double>(std::begin(kFixtureS3ClosedForm),
                                                           std::end(kFixtureS3ClosedForm))},
                      {"test",
                       {{"errors",
                         {{"r_p_ge_0.1", {{"max", 0.025}, {"rms", 0.0025}}},
                          {"r_p_lt_0.1", {{"max", 0.25}, {"rms", 0.006}}}}}}}};
  std::ofstream(dir / "gtso" / "gtso.json") << g.dump(2);
  nlohmann::json fit;
  fit["version"] = "fixture";
  const char* names[6] = {"a1", "a0", "b1", "b0", "c1", "c0"};
  for (int i = 0; i < 6; ++i) {
    fit["linear"][names[i]] = kFixtureCoeffs[i];
    fit["linear_se"][names[i]] = 0.001 * (i + 1);
  }
  fit["errors"]["refit"] = {{"rmse", 0.004}, {"max_abs", 0.03}};
  fit["shipped"]["max_curve_difference"] = {{"value", 0.02}, {"A", 0.5}, {"rho", 0.9}};
  fit["sweep"] = {{"spp", 256}, {"bounces", 3}};
  std::ofstream(dir / "fit.json") << fit.dump(2);
  // Readers require the output-set manifests `gtbake gtso` and `gtbake fit` write.
  sealOutputSet(dir / "gtso", "gtso", {"gtso3d.f32", "gtso4d.f32", "gtso.json"});
  sealOutputSet(dir, "fit", {"fit.json"});
}

std::array<double, 6> fixtureProfileCoeffs(int k) {
  // Monotone in A with G(1, rho) = 1 (a1 - b1 + c1 = 0, a0 - b0 + c0 = 1): passes the shipping
  // gate of docs/profiles.md §9.
  return {0.4 + 0.1 * k, 0.3, 0.9, 1.2, 0.5 - 0.1 * k, 1.9};
}

void writeProfileFixture(const std::filesystem::path& dir, const std::string& estimator, int k,
                         const std::string& claimed) {
  const std::filesystem::path d = dir / estimator;
  std::filesystem::create_directories(d);
  nlohmann::json fit;
  const char* names[6] = {"a1", "a0", "b1", "b0", "c1", "c0"};
  const std::array<double, 6> c = fixtureProfileCoeffs(k);
  for (int i = 0; i < 6; ++i) {
    fit["linear"][names[i]] = c[i];
    fit["linear_se"][names[i]] = 0.001;
  }
  fit["errors"]["shipped"] = {{"rmse", kFixtureProfilePaperRmse}};
  fit["errors"]["held_out_by_scene"] = {{"rmse", kFixtureProfileHeldOutRmse}};
  fit["scene_jackknife"]["band_max"] = {{"value", 0.002}};
  if (k < 2) {
    fit["profile"]["table"] = {{"needed", true},
                               {"A_nodes", 4},
                               {"rho", kFixtureTableRho[k]},
                               {"values", kFixtureTable[k]},
                               {"held_out_by_scene_rmse", kFixtureTableHeldOutRmse[k]}};
  }
  fit["input"] = {{"A", "screen-space"},
                  {"estimator", claimed.empty() ? estimator : claimed},
                  {"screen_ao", "../screen_ao"}};
  std::ofstream(d / "fit.json") << fit.dump(2);
  sealOutputSet(d, "fit", {"fit.json"});
}

}  // namespace gtbake::test
