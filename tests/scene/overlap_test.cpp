// No two pieces of a corpus scene overlap (docs/scenes.md, "Pieces that touch"): no coincident
// faces, no crossing surfaces, nothing inside a closed piece; the checker itself on small cases.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <iostream>
#include <map>

#include "mesh_overlap.h"
#include "scene/mesh_builder.h"
#include "scene/procedural_scenes.h"
#include "scene/scene_corpus.h"

namespace gtbake {
namespace {

const Eigen::Vector3d kX = Eigen::Vector3d::UnitX(), kY = Eigen::Vector3d::UnitY(),
                      kZ = Eigen::Vector3d::UnitZ();

test::OverlapReport overlapsOf(void (*build)(MeshBuilder&)) {
  MeshBuilder mesh;
  build(mesh);
  return test::findOverlaps(mesh.finish("case", {}));
}

// A box on the ground and a slab resting on the box: sealed contacts only.
TEST(MeshOverlap, TouchingPiecesAreContactsOnly) {
  const auto r = overlapsOf([](MeshBuilder& mesh) {
    addFlatGround(mesh, 2.0);
    addBox(mesh, {0, 0, 0}, 0.3, 0.3, 1.0, 0.0);
    addOrientedBox(mesh, {0, 1.1, 0}, kX, kY, kZ, {1.0, 0.1, 1.0});
  });
  EXPECT_EQ(r.pieces, 3u);
  EXPECT_EQ(r.closed_pieces, 2u);
  EXPECT_EQ(r.coincident, 0u);
  EXPECT_GT(r.contacts, 0u);
  EXPECT_EQ(r.crossings, 0u);
  EXPECT_EQ(r.enclosed, 0u);
}

// The former portico's fault: a slab through a wall, their top faces in one plane.
TEST(MeshOverlap, FindsCoincidentTopsAndCrossingSolids) {
  const auto r = overlapsOf([](MeshBuilder& mesh) {
    addOrientedBox(mesh, {0, 1.0, 0}, kX, kY, kZ, {2.0, 1.0, 0.1});
    addOrientedBox(mesh, {0, 1.9, 0.5}, kX, kY, kZ, {2.0, 0.1, 1.0});
  });
  EXPECT_GT(r.coincident, 0u);
  EXPECT_GT(r.crossings, 0u);
  EXPECT_NE(r.first.find("coincident"), std::string::npos);
}

TEST(MeshOverlap, FindsAPieceInsideAnother) {
  const auto r = overlapsOf([](MeshBuilder& mesh) {
    addBox(mesh, {0, 0, 0}, 1.0, 1.0, 2.0, 0.0);
    addBox(mesh, {0.1, 0.5, 0.2}, 0.2, 0.3, 0.4, 0.3);
  });
  EXPECT_EQ(r.enclosed, 1u);
  EXPECT_EQ(r.crossings, 0u);
  EXPECT_EQ(r.coincident, 0u);
}

// Every corpus scene (all twelve types, the default variants and seed): no coincident faces, and
// no crossing or enclosed pieces except where rocks lie in each other and in the ground, which is
// that type's content (crossing surfaces share no faces, so every tracer sees the same union).
TEST(Corpus, PiecesNeitherCoincideNorInterpenetrate) {
  std::map<std::string, test::OverlapReport> per_type;
  for (const auto& type : corpusTypeNames()) {
    for (int v = 0; v < kCorpusVariants; ++v) {
      const Scene scene = makeCorpusScene(type, v, 1);
      const test::OverlapReport r = test::findOverlaps(scene);
      EXPECT_EQ(r.coincident, 0u) << scene.name << ": " << r.first;
      if (type != "rocks") {
        EXPECT_EQ(r.crossings, 0u) << scene.name << ": " << r.first;
        EXPECT_EQ(r.enclosed, 0u) << scene.name;
      }
      test::OverlapReport& sum = per_type[type];
      sum.pieces += r.pieces;
      sum.closed_pieces += r.closed_pieces;
      sum.coincident += r.coincident;
      sum.contacts += r.contacts;
      sum.crossings += r.crossings;
      sum.enclosed += r.enclosed;
    }
  }
  std::cout << "type: pieces closed | coincident contacts crossings enclosed (6 variants)\n";
  for (const auto& [type, s] : per_type) {
    std::cout << type << ": " << s.pieces << " " << s.closed_pieces << " | " << s.coincident << " "
              << s.contacts << " " << s.crossings << " " << s.enclosed << "\n";
  }
}

}  // namespace
}  // namespace gtbake
