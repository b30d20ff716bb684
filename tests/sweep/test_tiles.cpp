// Tiles, shards, merge and resume (docs/cluster.md, docs/reproducibility.md): a pixel's values do
// not depend on which rectangle, shard or run traced it.
#include <gtest/gtest.h>

#include "scene/procedural_scenes.h"
#include "sweep/embree_tracer.h"
#include "sweep/escape_image.h"

namespace gtbake {
namespace {

// Tracing a rectangle gives, pixel for pixel and channel for channel, the bits of the whole image.
TEST(Tiles, RectangleEqualsTheSamePixelsOfTheWholeImage) {
  const Scene scene = makeSphereOnPlaneScene(1.0);
  const EmbreeTracer tracer(scene);
  WalkSettings settings;
  settings.spp = 8;
  settings.specular_roughness = {0.0, 0.4};
  settings.specular_spp = 8;
  settings.scene_key = sceneStreamKey("spheres");
  const int width = 23;
  const int height = 17;
  const EscapeImage whole =
      traceEscapeImage(tracer, scene.camera, width, height, settings, "", false);
  const PixelRect rect{5, 3, 19, 11};
  const EscapeImage part =
      traceEscapeImage(tracer, scene.camera, width, height, rect, settings, "", false);
  ASSERT_EQ(part.width, rect.width());
  ASSERT_EQ(part.height, rect.height());
  const std::vector<ExrChannel> a = escapeChannels(whole);
  const std::vector<ExrChannel> b = escapeChannels(part);
  ASSERT_EQ(a.size(), b.size());
  std::size_t unmasked = 0;
  for (std::size_t c = 0; c < a.size(); ++c) {
    ASSERT_EQ(a[c].name, b[c].name);
    for (int j = rect.y0; j < rect.y1; ++j) {
      for (int i = rect.x0; i < rect.x1; ++i) {
        const float full = a[c].pixels[static_cast<std::size_t>(j) * width + i];
        const float tile =
            b[c].pixels[static_cast<std::size_t>(j - rect.y0) * rect.width() + (i - rect.x0)];
        ASSERT_EQ(full, tile) << a[c].name << " at (" << i << ", " << j << ")";
      }
    }
  }
  for (std::uint8_t m : part.mask) unmasked += m;
  EXPECT_GT(unmasked, rect.pixels() / 2) << "the rectangle should mostly see geometry";
}

}  // namespace
}  // namespace gtbake
