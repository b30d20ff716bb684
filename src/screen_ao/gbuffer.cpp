#include "screen_ao/gbuffer.h"

#include <cmath>
#include <filesystem>
#include <string>

#include "common/error.h"
#include "common/image_io.h"
#include "sweep/camera_json.h"
#include "sweep/sweep_set.h"

namespace gtbake {

namespace {

const std::vector<float>& need(const std::map<std::string, std::vector<float>>& channels,
                               const std::string& name, std::size_t pixels,
                               const std::string& where) {
  const auto it = channels.find(name);
  if (it == channels.end()) {
    throw Error(where + " has no channel " + name +
                " (sweep it again with this gtbake: the G-buffer channels are new)");
  }
  if (it->second.size() != pixels) throw Error(where + ": channel " + name + " has another size");
  return it->second;
}

// The ray-traced truth as read, checked at every unmasked pixel (docs/limits.md §Values): A and
// every A_R in [0, 1], the bent normal finite.
void checkTruth(const SweepImage& image, const std::string& file) {
  const GBuffer& g = image.gbuffer;
  const auto unit = [](float v) { return v >= 0.0f && v <= 1.0f; };
  for (std::size_t p = 0; p < g.pixels(); ++p) {
    if (g.mask[p] == 0) continue;
    bool ok = unit(image.truth.a[p]);
    for (const auto& [name, values] : image.truth.a_at_radius) ok = ok && unit(values[p]);
    for (int c = 0; c < 3; ++c) ok = ok && std::isfinite(image.truth.bent[3 * p + c]);
    if (!ok) {
      throw Error(file + ": A or A_R outside [0, 1], or a non-finite BN, at pixel (" +
                  std::to_string(p % g.width) + ", " + std::to_string(p / g.width) + ")");
    }
  }
}

SweepImage readImage(const SweepSet& set, const SweepView& view) {
  SweepImage image;
  image.name = view.name;
  image.group = view.scene;
  if (view.camera.is_null()) {
    throw Error(set.where + " entry " + image.name +
                " has no camera (sweep it again with this gtbake)");
  }
  const PerspectiveCamera camera = cameraFromJson(view.camera, set.where + " entry " + image.name);
  const std::string& file = view.file;
  const std::shared_ptr<const ExrImage> shared =
      readVerifiedExr(set.manifest, file, file, {view.width, view.height, set.where});
  const ExrImage& exr = *shared;
  image.gbuffer = gbufferFromChannels(view.width, view.height, camera, exr.channels, file);
  const std::size_t pixels = image.gbuffer.pixels();
  image.truth.a = need(exr.channels, "A", pixels, file);
  for (const char* c : {"BNX", "BNY", "BNZ"}) need(exr.channels, c, pixels, file);
  image.truth.bent.resize(3 * pixels);
  for (int c = 0; c < 3; ++c) {
    const std::vector<float>& v = exr.channels.at(std::string("BN") + "XYZ"[c]);
    for (std::size_t p = 0; p < pixels; ++p) image.truth.bent[3 * p + c] = v[p];
  }
  for (double radius : set.settings.gbuffer_radii) {  // the A_R channels sweep.json lists
    const auto at = exr.channels.find(gbufferRadiusChannelName(radius));
    if (at != exr.channels.end()) image.truth.a_at_radius[at->first] = at->second;
  }
  checkTruth(image, file);
  return image;
}

}  // namespace

double GBuffer::pixelsPerMetre(double z) const {
  return 0.5 * height / (tan_half * z);
}

Eigen::Vector3d GBuffer::viewPoint(int i, int j, double z) const {
  const double sx = (2.0 * (i + 0.5) / width - 1.0) * tan_half * aspect;
  const double sy = (1.0 - 2.0 * (j + 0.5) / height) * tan_half;
  return {sx * z, sy * z, -z};
}

Eigen::Vector3d GBuffer::worldToView(const Eigen::Vector3d& w) const {
  return camera.basis.transpose() * w;
}

Eigen::Vector3d GBuffer::viewToWorld(const Eigen::Vector3d& v) const {
  return camera.basis * v;
}

void makeViewSpace(GBuffer* g) {
  g->tan_half = std::tan(0.5 * g->camera.yfov);
  g->aspect = static_cast<double>(g->width) / g->height;
  const std::size_t pixels = g->pixels();
  g->position.assign(3 * pixels, 0.0f);
  g->view_normal.assign(3 * pixels, 0.0f);
  g->texels.assign(pixels, Texel{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.0f, 0.0f});
  for (int j = 0; j < g->height; ++j) {
    for (int i = 0; i < g->width; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * g->width + i;
      if (g->mask[p] == 0) continue;
      const Eigen::Vector3d x = g->viewPoint(i, j, g->depth[p]);
      const Eigen::Vector3d n =
          g->worldToView(
               Eigen::Vector3d(g->normal[3 * p], g->normal[3 * p + 1], g->normal[3 * p + 2]))
              .normalized();
      Texel& t = g->texels[p];
      for (int c = 0; c < 3; ++c) {
        g->position[3 * p + c] = t.position[c] = static_cast<float>(x[c]);
        g->view_normal[3 * p + c] = t.normal[c] = static_cast<float>(n[c]);
      }
      t.depth = g->depth[p];
      t.plane = static_cast<float>(
          n.dot(Eigen::Vector3d(t.position[0], t.position[1], t.position[2]).cast<double>()));
    }
  }
}

GBuffer gbufferFromChannels(int width, int height, const PerspectiveCamera& camera,
                            const std::map<std::string, std::vector<float>>& channels,
                            const std::string& where) {
  GBuffer g;
  g.width = width;
  g.height = height;
  g.camera = camera;
  const std::size_t pixels = g.pixels();
  const std::vector<float>& mask = need(channels, "mask", pixels, where);
  g.depth = need(channels, "Z", pixels, where);
  const std::vector<float>* n[3] = {&need(channels, "NX", pixels, where),
                                    &need(channels, "NY", pixels, where),
                                    &need(channels, "NZ", pixels, where)};
  g.mask.resize(pixels);
  g.normal.resize(3 * pixels);
  for (std::size_t p = 0; p < pixels; ++p) {
    g.mask[p] = mask[p] > 0.5f ? 1 : 0;
    for (int c = 0; c < 3; ++c) g.normal[3 * p + c] = (*n[c])[p];
    if (g.mask[p] == 0) continue;
    const double length =
        std::sqrt(g.normal[3 * p] * g.normal[3 * p] + g.normal[3 * p + 1] * g.normal[3 * p + 1] +
                  g.normal[3 * p + 2] * g.normal[3 * p + 2]);
    if (!(g.depth[p] > 0.0f) || !std::isfinite(g.depth[p]) || !(std::abs(length - 1.0) < 1e-3)) {
      throw Error(where + ": pixel " + std::to_string(p) +
                  " has a depth <= 0 or a normal that is not unit length");
    }
  }
  makeViewSpace(&g);
  return g;
}

SweepImages readSweepImages(const std::filesystem::path& dir) {
  const SweepSet set = readSweepSet(dir);
  SweepImages result;
  result.sweep_version = set.version;
  for (const SweepView& view : set.views) result.images.push_back(readImage(set, view));
  return result;
}

}  // namespace gtbake
