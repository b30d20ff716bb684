#include "screen_ao/gbuffer_export.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/output_set.h"
#include "common/text_escape.h"
#include "common/threads.h"
#include "gtbake_version.h"
#include "texture/texture_containers.h"

namespace gtbake {

namespace {

using json = nlohmann::ordered_json;

json rowMajor(const Eigen::Matrix4d& m) {
  json rows = json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  return rows;
}

// The conventions every file follows, written into gbuffer.json (docs/screen_ao.md §8).
json layoutJson() {
  json j;
  j["view_space"] =
      "right-handed, metres: x right, y up, z backward (towards the camera), camera at the origin "
      "looking along -z";
  j["pixels"] =
      "row-major, row 0 at the top; pixel (i, j) has its centre at (i + 0.5, j + 0.5), NDC x = "
      "2(i + 0.5)/width - 1, NDC y = 1 - 2(j + 0.5)/height";
  j["matrices"] =
      "row-major (matrix[r][c] is row r, column c), acting on column vectors: p' = M p; view maps "
      "world to view space, projection maps view space to clip space (D3D/Vulkan depth range "
      "[0, 1], NDC y up)";
  j["depth"] = {{"exr_channel", "depth"},
                {"dds_format", "DXGI_FORMAT_R32_FLOAT"},
                {"meaning",
                 "linear view depth Z = -z_view > 0, metres; 0 where mask = 0; the pixel's "
                 "view-space point is Z (ndc_x / P[0][0], ndc_y / P[1][1], -1)"}};
  j["normal"] = {{"exr_channels", {"normal.X", "normal.Y", "normal.Z"}},
                 {"dds_format", "DXGI_FORMAT_R32G32B32A32_FLOAT"},
                 {"meaning",
                  "unit view-space geometric normal (x, y, z) as 32-bit floats, facing the "
                  "camera; the DDS's w is the mask; 0 where mask = 0"}};
  j["mask"] = {{"exr_channel", "mask"}, {"meaning", "1 = the pixel sees geometry, 0 = sky"}};
  j["import"] = {{"file", "<image>.exr (the images[] entry's name), same width and height"},
                 {"channels",
                  "A: the pass's ambient visibility in [0, 1]; optional BNX BNY BNZ: its unit "
                  "bent normal in world space (view space: VBNX VBNY VBNZ)"},
                 {"masked_pixels", "ignored (may hold anything)"}};
  return j;
}

json imageJson(const SweepImage& image, const std::string& slug) {
  const GBuffer& g = image.gbuffer;
  const double aspect = static_cast<double>(g.width) / g.height;
  json j;
  j["name"] = image.name;
  j["scene"] = image.group;
  j["exr"] = slug + ".exr";
  j["depth_dds"] = slug + ".depth.dds";
  j["normal_dds"] = slug + ".normal.dds";
  j["width"] = g.width;
  j["height"] = g.height;
  j["yfov"] = g.camera.yfov;
  j["aspect"] = aspect;
  j["near"] = kExportNear;
  j["far"] = kExportFar;
  j["camera_position"] = {g.camera.position.x(), g.camera.position.y(), g.camera.position.z()};
  j["view"] = rowMajor(exportViewMatrix(g.camera));
  j["projection"] = rowMajor(exportProjectionMatrix(g.camera.yfov, aspect));
  return j;
}

// The image's EXR and its two DDS files, staged into `output`.
void addImageFiles(OutputSet* output, const GBuffer& g, const std::string& slug) {
  const std::size_t pixels = g.pixels();
  std::vector<float> mask(pixels), normal[3], rgba(4 * pixels, 0.0f);
  for (auto& c : normal) c.assign(pixels, 0.0f);
  for (std::size_t p = 0; p < pixels; ++p) {
    mask[p] = g.mask[p] != 0 ? 1.0f : 0.0f;
    for (int c = 0; c < 3; ++c) {
      normal[c][p] = g.mask[p] != 0 ? g.view_normal[3 * p + c] : 0.0f;
      rgba[4 * p + c] = normal[c][p];
    }
    rgba[4 * p + 3] = mask[p];
  }
  output->add(slug + ".exr", encodeExr(g.width, g.height,
                                       {{"depth", g.depth},
                                        {"normal.X", normal[0]},
                                        {"normal.Y", normal[1]},
                                        {"normal.Z", normal[2]},
                                        {"mask", mask}}));
  output->add(slug + ".depth.dds", makeDdsFloat2d(g.width, g.height, 1, g.depth));
  output->add(slug + ".normal.dds", makeDdsFloat2d(g.width, g.height, 4, rgba));
}

}  // namespace

Eigen::Matrix4d exportViewMatrix(const PerspectiveCamera& camera) {
  Eigen::Matrix4d v = Eigen::Matrix4d::Identity();
  v.topLeftCorner<3, 3>() = camera.basis.transpose();
  // 0 − x rather than −x: a zero offset prints as 0.0, not −0.0.
  v.topRightCorner<3, 1>() = Eigen::Vector3d::Zero() - camera.basis.transpose() * camera.position;
  return v;
}

Eigen::Matrix4d exportProjectionMatrix(double yfov, double aspect) {
  const double f = 1.0 / std::tan(0.5 * yfov);
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = f / aspect;
  p(1, 1) = f;
  p(2, 2) = kExportFar / (kExportNear - kExportFar);
  p(2, 3) = kExportNear * kExportFar / (kExportNear - kExportFar);
  p(3, 2) = -1.0;
  return p;
}

void runGbufferExport(const GbufferExportOptions& o) {
  if (o.sweep.empty()) throw Error("no sweep directory given: pass --sweep DIR");
  if (o.out.empty()) throw Error("no output directory given: pass --out DIR");
  const ThreadLimit threads(o.threads);
  const SweepImages sweep = readSweepImages(o.sweep);
  OutputSet output(o.out, "gbuffer");
  json settings;
  settings["sweep"] = relativePath(o.sweep, o.out);
  json doc;
  doc["gtbake_version"] = GTBAKE_VERSION;
  doc["sweep_gtbake_version"] = sweep.sweep_version;
  doc["sweep"] = settings["sweep"];
  doc["layout"] = layoutJson();
  doc["images"] = json::array();
  for (const SweepImage& image : sweep.images) {
    const std::string slug = fileSlug(image.name);
    addImageFiles(&output, image.gbuffer, slug);
    doc["images"].push_back(imageJson(image, slug));
  }
  output.setSettings(settings);
  output.add("gbuffer.json", doc.dump(2) + "\n");
  output.commit();
}

}  // namespace gtbake
