#include "tiny_sweep.h"

#include "sweep/sweep_command.h"

namespace gtbake::test {

std::filesystem::path tinySweep(const std::filesystem::path& out,
                                const std::vector<std::string>& scenes) {
  SweepOptions o;
  for (const std::string& s : scenes) {
    o.scenes.push_back(std::filesystem::path(GTBAKE_SOURCE_DIR) / "data" / "scenes" /
                       (s + ".gltf"));
  }
  o.out = out;
  o.spp = 16;
  o.width = 48;
  o.height = 48;
  o.specular_roughness = {};
  o.progress = false;
  runSweep(o);
  return out;
}

}  // namespace gtbake::test
