// Geometry of the procedural scenes: closed-form shapes, watertightness, framing, determinism.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>

#include "common/error.h"
#include "common/math_constants.h"
#include "scene/mesh_builder.h"
#include "scene/procedural_scenes.h"
#include "scene_test_util.h"
#include "support/test_scenes.h"

namespace gtbake {
namespace {

bool onOuterRim(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  const auto far = [](const Eigen::Vector3f& p) {
    return std::max(std::abs(p.x()), std::abs(p.z())) >= 0.999 * kGroundExtent;
  };
  return far(a) && far(b);
}

bool onRoomTop(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  return a.y() == 2.5f && b.y() == 2.5f;
}

TEST(GradedAxis, SymmetricSortedDoublingAndExact) {
  const auto axis = gradedAxis(2.0, 0.5, 1000.0);
  EXPECT_EQ(axis.front(), -1000.0);
  EXPECT_EQ(axis.back(), 1000.0);
  for (std::size_t i = 0; i < axis.size(); ++i) EXPECT_EQ(axis[i], -axis[axis.size() - 1 - i]);
  for (std::size_t i = 1; i < axis.size(); ++i) {
    const double step = axis[i] - axis[i - 1];
    if (std::abs(axis[i]) <= 2.0 && std::abs(axis[i - 1]) <= 2.0) {
      EXPECT_EQ(step, 0.5);
    }
    if (i >= 2) {
      EXPECT_LE(step, 2.0 * (axis[i - 1] - axis[i - 2]) + 1e-9);
      EXPECT_GE(step, 0.5 * (axis[i - 1] - axis[i - 2]) - 1e-9);
    }
  }
  EXPECT_LT(axis.size(), 40u);
}

// Every scene is one sheet: edges shared by exactly two triangles with opposite directions
// (watertight and consistently oriented), boundary only at the world's rim (or the room's top).
TEST(SceneTopology, SevenScenesAreWatertightSheets) {
  for (const auto& name : sceneTypeNames()) {
    const Scene scene = makeSceneType(name, 1);
    const auto census = test::edgeCensus(scene);
    EXPECT_EQ(census.non_manifold, 0u) << name;
    EXPECT_EQ(census.inconsistent, 0u) << name;
    EXPECT_GT(census.boundary, 0u) << name;
    EXPECT_EQ(test::strayBoundaryEdges(scene, name == "corner" ? onRoomTop : onOuterRim), 0u)
        << name;
  }
}

TEST(SceneTopology, ClosedSolidsHaveNoBoundaryAndEulerTwo) {
  const auto check = [](const Scene& scene) {
    const auto census = test::edgeCensus(scene);
    EXPECT_EQ(census.boundary, 0u) << scene.name;
    EXPECT_EQ(census.non_manifold, 0u) << scene.name;
    EXPECT_EQ(census.inconsistent, 0u) << scene.name;
    const long euler = static_cast<long>(scene.positions.size()) - static_cast<long>(census.edges) +
                       static_cast<long>(scene.triangles.size());
    EXPECT_EQ(euler, 2) << scene.name;
  };
  MeshBuilder sphere, cylinder, box;
  addSphere(sphere, {0.3, 1.0, -2.0}, 1.0, 64);
  addCylinder(cylinder, {1.0, 0.0, 1.0}, 0.2, 2.0, 64);
  addBox(box, {0.0, 0.0, 0.0}, 0.5, 0.7, 1.1, 0.3);
  check(sphere.finish("sphere", {}));
  check(cylinder.finish("cylinder", {}));
  check(box.finish("box", {}));
  check(makeClosedBoxScene());
}

// Outward facing: the signed volume of a closed outward mesh is positive and matches.
TEST(SceneTopology, ClosedSolidsFaceOutwardWithTheRightVolume) {
  const auto volume = [](const Scene& s) {
    double v = 0.0;
    for (const auto& t : s.triangles) {
      v += s.positions[t[0]].cast<double>().dot(
               s.positions[t[1]].cast<double>().cross(s.positions[t[2]].cast<double>())) /
           6.0;
    }
    return v;
  };
  MeshBuilder sphere, box;
  addSphere(sphere, {0.3, 1.0, -2.0}, 1.0, 128);
  addBox(box, {0.0, 0.0, 0.0}, 0.5, 0.7, 1.1, 0.3);
  // An inscribed polyhedron: less than the ball, more than the ball shrunk to the facets'
  // smallest distance from the centre (at least R cos(2π/segments)).
  const double ball = 4.0 / 3.0 * kPi, shrink = std::cos(2.0 * kPi / 128);
  EXPECT_LT(volume(sphere.finish("s", {})), ball);
  EXPECT_GT(volume(sphere.finish("s", {})), ball * shrink * shrink * shrink);
  EXPECT_NEAR(volume(box.finish("b", {})), 1.0 * 1.4 * 1.1, 1e-6);
}

// The bowl is a spherical cap: every vertex below the ground on the sphere, the rim radius
// √(h(2R − h)), facets within the documented angle of the true normal, facing the centre.
TEST(SphericalCavity, VerticesOnTheSphereAndFacetsFaceTheCentre) {
  for (const double h : {0.3, 1.0, 1.8}) {
    const double R = 1.3;
    const Scene scene = makeSphericalCavityScene(R, h, kCurveSegments);
    const Eigen::Vector3d centre(0.0, R - h, 0.0);
    const double rim = std::sqrt(h * (2.0 * R - h));
    int below = 0, on_rim = 0;
    for (const auto& p : scene.positions) {
      const Eigen::Vector3d q = p.cast<double>();
      if (q.y() < -1e-9) {
        ++below;
        EXPECT_NEAR((q - centre).norm(), R, 2e-6 * R);
      } else if (std::abs(std::hypot(q.x(), q.z()) - rim) < 1e-5) {
        ++on_rim;
      }
    }
    EXPECT_EQ(on_rim, kCurveSegments) << h;
    EXPECT_GT(below, kCurveSegments * 2) << h;
    float lowest = 0.0f;
    for (const auto& p : scene.positions) lowest = std::min(lowest, p.y());
    EXPECT_NEAR(lowest, -h, 1e-6);
    double worst = 0.0;
    for (const auto& t : scene.triangles) {
      const Eigen::Vector3d a = scene.positions[t[0]].cast<double>();
      const Eigen::Vector3d b = scene.positions[t[1]].cast<double>();
      const Eigen::Vector3d c = scene.positions[t[2]].cast<double>();
      const Eigen::Vector3d mid = (a + b + c) / 3.0;
      if (mid.y() > -1e-9) continue;
      const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
      const double cosine = normal.dot((centre - mid).normalized());
      worst = std::max(worst, std::acos(std::min(1.0, cosine)));
    }
    std::printf("bowl R %.2f h %.2f: worst facet normal %.3f deg from the sphere's\n", R, h,
                worst * 180.0 / kPi);
    EXPECT_LT(worst, 2.0 * kPi / kCurveSegments) << h;  // docs: within one segment angle
  }
}

TEST(SceneCamera, CentreRaysHitTheNamedPoints) {
  const auto centreHit = [](const Scene& s) -> Eigen::Vector3d {
    const auto dist = test::castRay(s, s.camera.position, -s.camera.basis.col(2));
    EXPECT_TRUE(dist.has_value()) << s.name;
    if (!dist) return Eigen::Vector3d::Zero();
    return s.camera.position - *dist * s.camera.basis.col(2);
  };
  EXPECT_TRUE(
      centreHit(makeSphericalCavityScene(1.0, 0.6)).isApprox(Eigen::Vector3d(0, -0.6, 0), 1e-4));
  EXPECT_TRUE(
      centreHit(makeCylinderWellScene(0.5, 0.8)).isApprox(Eigen::Vector3d(0, -0.8, 0), 1e-6));
  EXPECT_NEAR(centreHit(makeVGrooveScene(kPi / 3, 0.7)).y(), -0.7, 1e-5);
  EXPECT_NEAR(centreHit(makeClosedBoxScene()).z(), -1.0, 1e-6);
  EXPECT_NEAR(centreHit(makeOpenPlaneScene()).y(), 0.0, 1e-6);
  EXPECT_GT(centreHit(makeSphereOnPlaneScene(0.5)).y(), 0.0);
}

// The cameras frame the features: on a 24 × 24 grid of pixel centres no ray sees the sky (the
// default 192² sweep agrees: sweep.json counts every pixel unmasked in all seven scenes).
TEST(SceneCamera, SevenScenesShowNoSky) {
  constexpr int kGrid = 24;
  for (const auto& name : sceneTypeNames()) {
    const Scene scene = makeSceneType(name, 1);
    int sky = 0;
    for (int j = 0; j < kGrid; ++j) {
      for (int i = 0; i < kGrid; ++i) {
        if (!test::castRay(scene, scene.camera.position,
                           test::pixelRay(scene.camera, i, j, kGrid, kGrid))) {
          ++sky;
        }
      }
    }
    EXPECT_EQ(sky, 0) << name << ": " << sky << " of " << kGrid * kGrid << " rays see the sky";
    EXPECT_NEAR(scene.camera.basis.determinant(), 1.0, 1e-12) << name;
  }
}

// docs/scenes.md's table of the seven scene types quotes each one's triangle count (seed 1): the
// numbers there are the builders' (digits grouped by spaces, "9 216 (seed 1)").
TEST(SceneDocs, TriangleCountsInTheTableAreTheBuilders) {
  const std::string doc =
      test::readBytes(std::filesystem::path(GTBAKE_SOURCE_DIR) / "docs" / "scenes.md");
  ASSERT_FALSE(doc.empty());
  for (const auto& name : sceneTypeNames()) {
    const std::regex row("\\| " + name + " \\|[^|\\n]*\\| ([0-9 ]+?)( \\(seed 1\\))? \\|");
    std::smatch match;
    ASSERT_TRUE(std::regex_search(doc, match, row)) << name << " has no row in docs/scenes.md";
    std::string digits = match[1];
    digits.erase(std::remove(digits.begin(), digits.end(), ' '), digits.end());
    EXPECT_EQ(std::stoul(digits), makeSceneType(name, 1).triangles.size()) << name;
  }
}

TEST(SeededScenes, SameSeedSameSceneOtherSeedOtherScene) {
  EXPECT_TRUE(test::scenesIdentical(makeClutterScene(3), makeClutterScene(3)));
  EXPECT_TRUE(test::scenesIdentical(makeTerrainScene(3), makeTerrainScene(3)));
  EXPECT_NE(makeClutterScene(3).positions, makeClutterScene(4).positions);
  EXPECT_NE(makeTerrainScene(3).positions, makeTerrainScene(4).positions);
  EXPECT_TRUE(test::scenesIdentical(makeCavityScene(), makeSceneType("cavity", 99)));
  EXPECT_THROW(makeSceneType("nope", 1), Error);
}

TEST(ClosedFormScenes, RejectBadParameters) {
  EXPECT_THROW(makeSphericalCavityScene(1.0, 2.5), Error);
  EXPECT_THROW(makeSphericalCavityScene(-1.0, 0.5), Error);
  EXPECT_THROW(makeCylinderWellScene(0.5, 1.0, 12), Error);
  EXPECT_THROW(makeVGrooveScene(4.0, 1.0), Error);
}

}  // namespace
}  // namespace gtbake
