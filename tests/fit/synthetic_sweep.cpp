#include "synthetic_sweep.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "common/atomic_file.h"
#include "common/image_io.h"
#include "common/output_set.h"
#include "fit/multibounce_fit.h"

namespace gtbake::test {

namespace fs = std::filesystem;

SweepData knownCoefficientSweep(const MultiBounceCoeffs& coeffs, std::size_t n, double sigma_A,
                                double sigma_G, double correlation, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  SweepData data;
  data.dir = "synthetic";
  data.spp = 2;
  data.bounces = 3;
  data.albedos = kAlbedos;
  data.scenes.push_back({"synthetic", 0, n, "", ""});
  for (PointSet* set : {&data.full, &data.half[0], &data.half[1]}) set->G.resize(kAlbedos.size());
  for (std::size_t i = 0; i < n; ++i) {
    const double a = uniform(rng);
    double full_A = 0.0;
    std::vector<double> full_G(kAlbedos.size(), 0.0);
    for (int h = 0; h < 2; ++h) {
      const double zA = normal(rng);
      const double A = a + sigma_A * zA;
      data.half[h].A.push_back(A);
      full_A += 0.5 * A;
      for (std::size_t j = 0; j < kAlbedos.size(); ++j) {
        const double G = evalMultiBounce(coeffs, a, kAlbedos[j]) + sigma_G * normal(rng) +
                         correlation * sigma_A * zA;
        data.half[h].G[j].push_back(G);
        full_G[j] += 0.5 * G;
      }
    }
    data.full.A.push_back(full_A);
    for (std::size_t j = 0; j < kAlbedos.size(); ++j) data.full.G[j].push_back(full_G[j]);
  }
  return data;
}

void appendScene(const SweepData& from, std::size_t s, SweepData& to, int copies) {
  if (to.albedos.empty()) {
    to.dir = from.dir;
    to.spp = from.spp;
    to.bounces = from.bounces;
    to.albedos = from.albedos;
    for (PointSet* set : {&to.full, &to.half[0], &to.half[1]}) set->G.resize(from.albedos.size());
  }
  const SweepScene& scene = from.scenes[s];
  const auto b = static_cast<std::ptrdiff_t>(scene.begin);
  const auto e = static_cast<std::ptrdiff_t>(scene.end);
  const std::size_t begin = to.full.A.size();
  for (int c = 0; c < copies; ++c) {
    const PointSet* src[3] = {&from.full, &from.half[0], &from.half[1]};
    PointSet* dst[3] = {&to.full, &to.half[0], &to.half[1]};
    for (int k = 0; k < 3; ++k) {
      dst[k]->A.insert(dst[k]->A.end(), src[k]->A.begin() + b, src[k]->A.begin() + e);
      for (std::size_t j = 0; j < from.albedos.size(); ++j) {
        dst[k]->G[j].insert(dst[k]->G[j].end(), src[k]->G[j].begin() + b, src[k]->G[j].begin() + e);
      }
    }
  }
  to.scenes.push_back({scene.name, begin, to.full.A.size(), scene.cluster, scene.type});
}

SweepData pooledSweep(const std::vector<SyntheticScene>& scenes, double sigma_A, double sigma_G,
                      double correlation, std::uint64_t seed) {
  SweepData data;
  for (const SyntheticScene& scene : scenes) {
    SweepData one =
        knownCoefficientSweep(scene.coeffs, scene.points, sigma_A, sigma_G, correlation, seed++);
    one.scenes[0].name = scene.name;
    appendScene(one, 0, data);
  }
  return data;
}

std::vector<double> cavityLaw(double A, int bounces) {
  std::vector<double> p;
  for (int k = 0; k <= bounces; ++k) p.push_back(A * std::pow(1.0 - A, k));
  return p;
}

void writeWalkSweep(const fs::path& dir, const std::vector<std::string>& scenes, int width,
                    int height, int spp, int bounces, const EscapeLaw& law, std::uint64_t seed) {
  ensureDirectory(dir);
  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  nlohmann::json doc;
  doc["settings"] = {{"spp", spp},         {"width", width},     {"height", height},
                     {"bounces", bounces}, {"radius", nullptr},  {"seed", seed},
                     {"threads", 1},       {"albedos", kAlbedos}};
  doc["views"] = nlohmann::json::array();
  doc["version"] = "test";
  std::vector<std::string> files;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (const std::string& name : scenes) {
    // channels[s][k]: s = 0 full, 1 = H0, 2 = H1; k = 0 is A.
    std::vector<std::vector<std::vector<float>>> p(
        3, std::vector<std::vector<float>>(bounces + 1, std::vector<float>(pixels, 0.0f)));
    std::vector<float> mask(pixels, 1.0f);
    std::size_t unmasked = 0;
    for (std::size_t i = 0; i < pixels; ++i) {
      if (static_cast<int>(i) < width) mask[i] = 0.0f;  // first row "sees the sky"
      unmasked += mask[i] > 0.5f;
      const std::vector<double> law_p = law((i + 0.5) / pixels);
      std::vector<double> counts[2] = {std::vector<double>(bounces + 1, 0.0),
                                       std::vector<double>(bounces + 1, 0.0)};
      for (int s = 0; s < spp; ++s) {
        double u = uniform(rng);
        for (int k = 0; k <= bounces; ++k) {
          if (u < law_p[k]) {
            counts[s % 2][k] += 1.0;
            break;
          }
          u -= law_p[k];
        }
      }
      const double n_half[2] = {double((spp + 1) / 2), double(spp / 2)};
      for (int k = 0; k <= bounces; ++k) {
        for (int h = 0; h < 2; ++h) p[1 + h][k][i] = float(counts[h][k] / n_half[h]);
        p[0][k][i] = float((counts[0][k] + counts[1][k]) / spp);
      }
    }
    std::vector<ExrChannel> channels;
    const char* prefix[3] = {"", "H0.", "H1."};
    for (int s = 0; s < 3; ++s) {
      channels.push_back({std::string(prefix[s]) + "A", p[s][0]});
      for (int k = 1; k <= bounces; ++k) {
        channels.push_back({std::string(prefix[s]) + "P" + std::to_string(k), p[s][k]});
      }
    }
    for (double rho : kAlbedos) {
      std::vector<float> g(pixels);
      for (std::size_t i = 0; i < pixels; ++i) {
        double value = 0.0;
        for (int k = bounces; k >= 0; --k) value = value * rho + p[0][k][i];
        g[i] = float(value);
      }
      channels.push_back({albedoChannel(rho), g});
    }
    channels.push_back({"mask", mask});
    writeExr(dir / (name + ".exr"), width, height, channels,
             {{"gtbake.spp", std::to_string(spp)},
              {"gtbake.bounces", std::to_string(bounces)},
              {"gtbake.seed", std::to_string(seed)},
              {"gtbake.scene", name + ".gltf"}});
    files.push_back(name + ".exr");
    doc["views"].push_back({{"name", name},
                            {"file", name + ".exr"},
                            {"gltf", name + ".gltf"},
                            {"width", width},
                            {"height", height},
                            {"unmasked_pixels", unmasked},
                            {"seconds", 0.0},
                            {"rays", 0},
                            {"rays_per_second", 0.0}});
  }
  writeFileAtomically(dir / "sweep.json", doc.dump(2));
  files.push_back("sweep.json");
  sealOutputSet(dir, "sweep", files);  // readers require the manifest (output_set.h)
}

MultiBounceCoeffs cavityLawOwnFit(int bounces, const std::function<double(double)>& regressor) {
  constexpr int kGrid = 20001;
  const auto x = [&](double A) { return regressor ? regressor(A) : A; };
  Eigen::MatrixXd X(kGrid, 3);
  for (int i = 0; i < kGrid; ++i) {
    const double v = x((i + 0.5) / kGrid);
    X.row(i) << v * v * v, -v * v, v;
  }
  Eigen::MatrixXd coeffs(kAlbedos.size(), 3);
  for (std::size_t j = 0; j < kAlbedos.size(); ++j) {
    Eigen::VectorXd y(kGrid);
    for (int i = 0; i < kGrid; ++i) {
      const std::vector<double> p = cavityLaw((i + 0.5) / kGrid, bounces);
      double g = 0.0;
      for (int k = 0; k <= bounces; ++k) g += std::pow(kAlbedos[j], k) * p[k];
      y[i] = g;
    }
    coeffs.row(j) = X.colPivHouseholderQr().solve(y).transpose();
  }
  Eigen::MatrixXd R(kAlbedos.size(), 2);
  for (std::size_t j = 0; j < kAlbedos.size(); ++j) R.row(j) << kAlbedos[j], 1.0;
  MultiBounceCoeffs out;
  for (int q = 0; q < 3; ++q) {
    const Eigen::Vector2d line = R.colPivHouseholderQr().solve(coeffs.col(q));
    out[2 * q] = line[0];
    out[2 * q + 1] = line[1];
  }
  return out;
}

namespace {

// The pid keeps tests that CTest runs in parallel (one process each) out of each other's way.
fs::path processRoot() {
  return fs::path(::testing::TempDir()) / ("gtbake_fit_" + std::to_string(::getpid()));
}

class RemoveTempRoot : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(processRoot(), ignored);
  }
};

[[maybe_unused]] ::testing::Environment* const kRemoveTempRoot =
    ::testing::AddGlobalTestEnvironment(new RemoveTempRoot);

}  // namespace

fs::path freshDir(const std::string& name) {
  const fs::path dir = processRoot() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace gtbake::test
