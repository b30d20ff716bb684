#include "validate_gtso/specular_sweep.h"

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/image_io.h"
#include "common/input_limits.h"
#include "common/output_set.h"
#include "sweep/escape_image.h"

namespace gtbake {

namespace {

namespace fs = std::filesystem;

const std::vector<float>& need(const ExrImage& image, const std::string& name,
                               const std::string& file, const char* hint) {
  const auto it = image.channels.find(name);
  if (it == image.channels.end()) throw Error(file + ": no channel " + name + " " + hint);
  return it->second;
}

}  // namespace

SpecularSweep readSpecularSweep(const fs::path& dir) {
  const fs::path json_path = dir / "sweep.json";
  if (!fs::is_regular_file(json_path))
    throw Error(dir.string() + " is not a sweep directory (no sweep.json); run `gtbake sweep`");
  // The sweep is one output set: every file read is verified against its manifest.
  const OutputManifest set = readOutputSet(dir, "sweep");
  const nlohmann::json json = parseJsonText(set.readVerified("sweep.json"), json_path.string());
  constexpr const char* kNoSpecular =
      "has no specular channels (S010 ...): trace it with gtbake sweep --specular-roughness LIST "
      "(the default traces 0.1,0.25,0.4,0.6,0.8; 'none' turns them off)";
  SpecularSweep sweep;
  sweep.dir = dir;
  try {
    const nlohmann::json& settings = json.at("settings");
    sweep.spp = static_cast<int>(jsonInteger(settings, "spp", 2, 1 << 20, json_path.string()));
    if (!settings.contains("specular_roughness") || settings["specular_roughness"].empty()) {
      throw Error("sweep " + dir.string() + " " + kNoSpecular);
    }
    sweep.roughness = settings["specular_roughness"].get<std::vector<double>>();
    sweep.specular_spp =
        static_cast<int>(jsonInteger(settings, "specular_spp", 0, 1 << 20, json_path.string()));
    for (const nlohmann::json& entry : json.at("scenes")) {
      SpecularScene scene;
      scene.name = entry.at("name").get<std::string>();
      if (entry.contains("scene")) {
        if (!entry["scene"].is_string())
          throw Error(json_path.string() + ": scene must be a string");
        scene.cluster = entry["scene"].get<std::string>();
      }
      if (entry.contains("type")) {
        if (!entry["type"].is_string()) throw Error(json_path.string() + ": type must be a string");
        scene.type = entry["type"].get<std::string>();
      }
      const std::string file = entry.at("file").get<std::string>();
      fileInsideDirectory(dir, file, json_path.string());
      ExrExpect expect;
      expect.width = static_cast<int>(jsonInteger(entry, "width", 1, 1 << 16, json_path.string()));
      expect.height =
          static_cast<int>(jsonInteger(entry, "height", 1, 1 << 16, json_path.string()));
      expect.source = json_path.string();
      const ExrImage image = decodeExr(set.readVerified(file), (dir / file).string(), expect);
      const std::string where = (dir / file).string();
      scene.width = image.width;
      scene.height = image.height;
      const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
      const std::vector<float>& mask = need(image, "mask", where, "(not a gtbake sweep EXR)");
      scene.mask.resize(pixels);
      for (std::size_t p = 0; p < pixels; ++p) scene.mask[p] = mask[p] != 0.0f ? 1 : 0;
      scene.A = need(image, "A", where, "(not a gtbake sweep EXR)");
      const char* kVectors = "(traced by an older gtbake sweep: rerun it)";
      for (const char* prefix : {"N", "V", "BN"}) {
        std::vector<float>& out = prefix[0] == 'N'   ? scene.normal
                                  : prefix[0] == 'V' ? scene.view
                                                     : scene.bent;
        out.resize(3 * pixels);
        int c = 0;
        for (const char* axis : {"X", "Y", "Z"}) {
          const std::vector<float>& ch = need(image, prefix + std::string(axis), where, kVectors);
          for (std::size_t p = 0; p < pixels; ++p) out[3 * p + c] = ch[p];
          ++c;
        }
      }
      for (double r : sweep.roughness) {
        const std::string name = specularChannelName(r);
        if (image.channels.count(name) == 0) throw Error(where + " " + kNoSpecular);
        scene.S.push_back(need(image, name, where, kNoSpecular));
        scene.H0.push_back(need(image, "H0." + name, where, kNoSpecular));
        scene.H1.push_back(need(image, "H1." + name, where, kNoSpecular));
      }
      sweep.scenes.push_back(std::move(scene));
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(json_path.string() + ": unexpected layout (" + std::string(e.what()) + ")");
  }
  if (sweep.scenes.empty()) throw Error(json_path.string() + " lists no scenes");
  return sweep;
}

}  // namespace gtbake
