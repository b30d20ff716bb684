#include "gbuffer_scenes.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "scene/mesh_builder.h"
#include "scene/procedural_scenes.h"
#include "sweep/escape_image.h"

namespace gtbake::test {

Scene grooveField(double w, double d, double height) {
  MeshBuilder mesh;
  const std::vector<double> xs = gradedAxis(w, w, kGroundExtent);
  const std::vector<double> zs = gradedAxis(w, w, kGroundExtent);
  addHeightfield(mesh, xs, zs,
                 [&](double x, double) { return -d * std::max(0.0, 1.0 - std::abs(x) / w); });
  return mesh.finish("groove", lookAt({0.0, height, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, 0.5));
}

Scene cornerField(double h) {
  MeshBuilder mesh;
  const std::vector<double> axis = gradedAxis(0.01, 0.01, kGroundExtent);
  addHeightfield(mesh, axis, axis, [&](double x, double z) {
    return h * std::clamp(std::max(x, z) / 0.01, 0.0, 1.0);
  });
  return mesh.finish("corner",
                     lookAt({-0.45, 1.6, -0.45}, {-0.3, 0.0, -0.3}, {0.0, 0.0, -1.0}, 0.6));
}

Scene openField() {
  MeshBuilder mesh;
  const std::vector<double> axis = gradedAxis(1.0, 1.0, kGroundExtent);
  addHeightfield(mesh, axis, axis, [](double, double) { return 0.0; });
  return mesh.finish("open", lookAt({0.0, 1.0, 0.0}, {0.0, 0.0, -1.0}, {0.0, 1.0, 0.0}, 0.8));
}

SweepImage traceImage(const Scene& scene, int width, int height, int spp, double radius,
                      std::uint64_t seed) {
  const EmbreeTracer tracer(scene);
  WalkSettings settings;
  settings.spp = spp;
  settings.bounces = 1;
  settings.seed = seed;
  settings.gbuffer_radii = {static_cast<float>(radius)};
  const EscapeImage traced =
      traceEscapeImage(tracer, scene.camera, width, height, settings, "", false);
  std::map<std::string, std::vector<float>> channels;
  for (ExrChannel& c : escapeChannels(traced)) channels[c.name] = std::move(c.pixels);
  SweepImage image;
  image.name = scene.name;
  image.group = scene.name;
  image.gbuffer = gbufferFromChannels(width, height, scene.camera, channels, scene.name);
  image.truth.a = channels.at("A");
  image.truth.bent.resize(3 * image.gbuffer.pixels());
  for (std::size_t p = 0; p < image.gbuffer.pixels(); ++p) {
    for (int c = 0; c < 3; ++c) {
      image.truth.bent[3 * p + c] = channels.at(std::string("BN") + "XYZ"[c])[p];
    }
  }
  image.truth.a_at_radius[gbufferRadiusChannelName(radius)] =
      channels.at(gbufferRadiusChannelName(radius));
  return image;
}

}  // namespace gtbake::test
