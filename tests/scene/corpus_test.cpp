// The scene corpus (twelve types × seeded variants) and the automatic cameras.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <set>
#include <utility>

#include "common/error.h"
#include "common/math_constants.h"
#include "scene/auto_camera.h"
#include "scene/procedural_scenes.h"
#include "scene/scene_corpus.h"
#include "scene_test_util.h"

namespace gtbake {
namespace {

TEST(Corpus, TwelveTypesNamedAndTypedVariantZeroIsClassic) {
  const auto& types = corpusTypeNames();
  ASSERT_EQ(types.size(), 12u);
  EXPECT_EQ(std::set<std::string>(types.begin(), types.end()).size(), 12u);
  for (std::size_t t = 0; t < sceneTypeNames().size(); ++t) {
    EXPECT_EQ(types[t], sceneTypeNames()[t]);
    Scene classic = makeSceneType(types[t], 5);
    const Scene variant = makeCorpusScene(types[t], 0, 5);
    EXPECT_EQ(variant.name, types[t] + "_0");
    EXPECT_EQ(variant.type, types[t]);
    classic.name = variant.name;
    EXPECT_TRUE(test::scenesIdentical(classic, variant)) << types[t];
  }
  EXPECT_THROW(makeCorpusScene("nope", 0, 1), Error);
  EXPECT_THROW(makeCorpusScene("rocks", -1, 1), Error);
}

// A pure function of (type, variant, seed); other variants and other seeds change the geometry.
TEST(Corpus, VariantsAreSeededAndDiffer) {
  for (const auto& type : corpusTypeNames()) {
    const Scene a = makeCorpusScene(type, 2, 1);
    EXPECT_TRUE(test::scenesIdentical(a, makeCorpusScene(type, 2, 1))) << type;
    EXPECT_NE(a.positions, makeCorpusScene(type, 3, 1).positions) << type;
    EXPECT_NE(a.positions, makeCorpusScene(type, 2, 2).positions) << type;
    EXPECT_EQ(a.name, type + "_2");
    EXPECT_EQ(a.type, type);
  }
}

// Every default corpus camera sees geometry in every pixel of an 8 × 8 grid (the 128² corpus
// sweep agrees: every pixel of all 72 views is unmasked), and its basis is a rotation.
TEST(Corpus, DefaultCorpusShowsNoSky) {
  constexpr int kGrid = 8;
  for (const auto& type : corpusTypeNames()) {
    for (int v = 0; v < kCorpusVariants; ++v) {
      const Scene scene = makeCorpusScene(type, v, 1);
      int sky = 0;
      for (int j = 0; j < kGrid; ++j) {
        for (int i = 0; i < kGrid; ++i) {
          sky += !test::castRay(scene, scene.camera.position,
                                test::pixelRay(scene.camera, i, j, kGrid, kGrid));
        }
      }
      EXPECT_EQ(sky, 0) << scene.name;
      EXPECT_NEAR(scene.camera.basis.determinant(), 1.0, 1e-12) << scene.name;
    }
  }
}

// Closed solids of the new building blocks (box, extrusion, tube, prism): no boundary,
// consistently oriented.
TEST(Corpus, BuildingBlocksAreClosedAndOriented) {
  MeshBuilder mesh;
  const Eigen::Vector3d a0 = Eigen::Vector3d(1, 1, 0).normalized();
  const Eigen::Vector3d a1 = Eigen::Vector3d(-1, 1, 0).normalized();
  addOrientedBox(mesh, {0, 1, 0}, a0, a1, a0.cross(a1), {0.5, 0.2, 0.1});
  std::vector<Eigen::Vector2d> star;
  for (int k = 0; k < 10; ++k) {
    const double r = k % 2 ? 0.5 : 1.0, t = -2.0 * kPi * k / 10;
    star.emplace_back(r * std::cos(t), r * std::sin(t));
  }
  addExtrusion(mesh, {4, 0, 0}, star, 0.3);
  addTube(mesh, {-4, 0, 0}, 0.5, 0.8, 1.0, 16);
  // An L section (bars 2 × 0.5 and 0.5 × 1.5, area 1.5) fanned from the square they share,
  // extruded 1 along z.
  PrismSection ell;
  const int centre = ell.add(0.25, 0.25);
  for (const auto& [x, y] :
       {std::pair{0.0, 0.0}, {2.0, 0.0}, {2.0, 0.5}, {0.5, 0.5}, {0.5, 1.5}, {0.0, 1.5}}) {
    ell.outline.push_back(ell.add(x, y));
  }
  for (std::size_t k = 0; k < 6; ++k) {
    ell.triangles.push_back({centre, ell.outline[k], ell.outline[(k + 1) % 6]});
  }
  addPrism(mesh, ell, {0, 0, 4}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), -0.5, 0.5);
  const Scene scene = mesh.finish("blocks", {});
  const auto census = test::edgeCensus(scene);
  EXPECT_EQ(census.boundary, 0u);
  EXPECT_EQ(census.non_manifold, 0u);
  EXPECT_EQ(census.inconsistent, 0u);
  // Outward: the signed volume Σ (a · (b × c)) / 6 is the sum of the three solids' volumes.
  double volume = 0.0;
  for (const auto& t : scene.triangles) {
    volume += scene.positions[t[0]].cast<double>().dot(scene.positions[t[1]].cast<double>().cross(
                  scene.positions[t[2]].cast<double>())) /
              6.0;
  }
  const double star_area = 10 * 0.5 * 1.0 * 0.5 * std::sin(2.0 * kPi / 10);
  const double tube = 16 * 0.5 * std::sin(2.0 * kPi / 16) * (0.64 - 0.25);
  EXPECT_NEAR(volume, 1.0 * 0.4 * 0.2 + 0.3 * star_area + tube + 1.5, 1e-5);
}

TEST(AutoCamera, ParsesAutoAndAutoK) {
  EXPECT_EQ(parseAutoCamera("auto"), kAutoViews);
  EXPECT_EQ(parseAutoCamera("auto:1"), 1);
  EXPECT_EQ(parseAutoCamera("auto:64"), 64);
  EXPECT_EQ(parseAutoCamera(""), 0);
  EXPECT_EQ(parseAutoCamera("camera"), 0);
  EXPECT_THROW(parseAutoCamera("auto:0"), Error);
  EXPECT_THROW(parseAutoCamera("auto:65"), Error);
  EXPECT_THROW(parseAutoCamera("auto:x"), Error);
  EXPECT_THROW(parseAutoCamera("auto:"), Error);
}

// View k looks at the box centre from azimuth 45° + 360° k/K, elevation 35°; every corner
// projects inside the image and the tightest one touches its edge (the box fills the frame).
TEST(AutoCamera, ViewsFrameTheBoundingBoxFromTheDocumentedDirections) {
  MeshBuilder mesh;
  addBox(mesh, {1.0, -0.5, 2.0}, 1.5, 0.4, 2.0, 0.0);  // x ∈ [−0.5, 2.5], y ∈ [−0.5, 1.5]
  const Scene scene = mesh.finish("box", {});
  const Eigen::Vector3d centre(1.0, 0.5, 2.0);
  for (double aspect : {1.0, 2.0, 0.5}) {
    const auto cameras = autoCameras(scene, 3, aspect);
    ASSERT_EQ(cameras.size(), 3u);
    for (int k = 0; k < 3; ++k) {
      const PerspectiveCamera& c = cameras[k];
      const double azimuth = kPi / 4 + 2 * kPi * k / 3, elevation = 35.0 * kPi / 180.0;
      const Eigen::Vector3d back(std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                                 std::cos(elevation) * std::cos(azimuth));
      EXPECT_TRUE((c.position - centre).normalized().isApprox(back, 1e-6));  // float box
      EXPECT_TRUE(c.basis.col(2).isApprox(back, 1e-12));
      EXPECT_NEAR(c.basis.determinant(), 1.0, 1e-12);
      EXPECT_NEAR(c.basis.col(0).y(), 0.0, 1e-12);  // no roll: +Y up in the image
      EXPECT_DOUBLE_EQ(c.yfov, kAutoCameraFov);
      double widest = 0.0;
      for (const auto& p : scene.positions) {
        const Eigen::Vector3d q = c.basis.transpose() * (p.cast<double>() - c.position);
        ASSERT_LT(q.z(), 0.0);  // in front
        const double ty = std::tan(0.5 * c.yfov);
        widest = std::max(
            {widest, std::abs(q.x() / -q.z()) / (ty * aspect), std::abs(q.y() / -q.z()) / ty});
      }
      EXPECT_NEAR(widest, 1.0, 1e-9) << "aspect " << aspect << " view " << k;
    }
  }
}

}  // namespace
}  // namespace gtbake
