// Fuzz target: the readers of shards and of the later stages' sets (docs/limits.md §Values). The
// first byte picks one; the rest is the file, sealed into a valid output set so the reader's own
// checks (not just the manifest's hash) are exercised:
//   0 shard.json (readShardManifest)          1 a checkpointed tile (decodeTile)
//   2 validate_gtso.json (applyValidateGtsoU)  3 sweep.json of a specular sweep (readSpecularSweep)
//   4 encode.json (readShippedVolumes, beside the volumes of a tiny gtso + encode)
//   5 tune.json (readTunedSettings)
// Seeds come from real runs: a two-shard sweep of a closed box, gtso at size 4 and its encode.
// Anything but a gtbake::Error is a bug.
#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_set.h"
#include "encode/encode_command.h"
#include "encode/shipped_volumes.h"
#include "fuzz_target.h"
#include "gtso/gtso_command.h"
#include "scene/procedural_scenes.h"
#include "support/test_scenes.h"
#include "sweep/shard_manifest.h"
#include "sweep/sweep_command.h"
#include "sweep/tile_store.h"
#include "tune/tune_set.h"
#include "validate_gtso/specular_sweep.h"
#include "validate_gtso/validate_gtso_set.h"

namespace gtbake::fuzz {

namespace {

namespace fs = std::filesystem;

// A shard (shard 0 of 2) and a whole sweep of a closed box with one specular channel.
const fs::path& fixtures() {
  static const fs::path dir = [] {
    const fs::path root = fs::path(scratchDir()) / "sets";
    writeGltfScene(root / "scenes" / "box.gltf", makeClosedBoxScene());
    SweepOptions o;
    o.scenes = {root / "scenes"};
    o.spp = 2;
    o.width = o.height = 8;
    o.bounces = 1;
    o.specular_roughness = {0.4};
    o.specular_spp = 2;
    o.threads = 1;
    o.progress = false;
    o.out = root / "sweep";
    runSweep(o);
    o.shards = 2;
    o.out = root / "shard";
    runSweep(o);
    ensureDirectory(root / "validate");
    GtsoOptions g;
    g.out = root / "gtso";
    g.size = 4;
    g.lobe_cells = 8;
    g.error_lobes = 16;
    g.error_seeds = 1;
    g.closed_form_lobes = 64;
    g.threads = 1;
    g.progress = false;
    runGtso(g);
    EncodeOptions e;
    e.gtso = g.out;
    e.out = root / "encode";
    e.threads = 1;
    e.progress = false;
    e.layout_lobes = 16;
    runEncode(e);
    return root;
  }();
  return dir;
}

// Reseals the set `command` of `dir` over the files it lists (one just rewritten with the
// fuzzed bytes).
void reseal(const fs::path& dir, const std::string& command) {
  std::vector<std::string> names;
  for (const OutputFile& f : readOutputSet(dir, command).files) names.push_back(f.name);
  sealOutputSet(dir, command, names);
}

// The one tile of the shard's set.
std::string tileName() {
  for (const OutputFile& f : readOutputSet(fixtures() / "shard", kShardSet).files) {
    if (f.name != "shard.json") return f.name;
  }
  throw Error("the fixture shard has no tile");
}

}  // namespace

std::vector<std::string> seeds() {
  const fs::path& dir = fixtures();
  const nlohmann::json validate = {{"u", 0.07}, {"u_interval", {0.02, 0.2}}, {"u_se", 0.03}};
  // One tuned setting with every field export reads (tune.json results/<estimator>/<setting>).
  const nlohmann::json refit = {{"a1", 0.5}, {"a0", 1.25}, {"b1", 0.75},
                                {"b0", 1.5}, {"c1", 0.25}, {"c0", 1.0}};
  const nlohmann::json profile = {{"value", 2.5},
                                  {"interval", {2.0, 3.0}},
                                  {"at_bound", false},
                                  {"grid_best", {{"value", 2.0}, {"profile_held_out", 0.125}}},
                                  {"refit", refit}};
  const nlohmann::json tune = {
      {"results",
       {{"gtao-runtime",
         {{"radius",
           {{"default", 1.0},
            {"optimum", {{"paper", {{"value", 4.0}}}, {"profile", profile}}}}}}}}}};
  return {std::string(1, '\0') + readFile(dir / "shard" / "shard.json"),
          std::string(1, '\1') + readFile(dir / "shard" / tileName()),
          std::string(1, '\2') + validate.dump(),
          std::string(1, '\3') + readFile(dir / "sweep" / "sweep.json"),
          std::string(1, '\4') + readFile(dir / "encode" / "encode.json"),
          std::string(1, '\5') + tune.dump()};
}

}  // namespace gtbake::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gtbake;
  namespace fs = std::filesystem;
  if (size < 1) return 0;
  const fs::path& dir = fuzz::fixtures();
  const std::string_view doc(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    switch (data[0] % 6) {
      case 0: {
        const std::string tile = fuzz::tileName();
        writeFileAtomically(dir / "shard" / "shard.json", doc);
        sealOutputSet(dir / "shard", kShardSet, {"shard.json", tile});
        readShardManifest(dir / "shard");
        break;
      }
      case 1:
        decodeTile(doc, "fuzz.tile");
        break;
      case 2: {
        writeFileAtomically(dir / "validate" / "validate_gtso.json", doc);
        sealOutputSet(dir / "validate", "validate_gtso", {"validate_gtso.json"});
        GtsoInput gtso;
        applyValidateGtsoU(dir / "validate" / "validate_gtso.json", &gtso);
        break;
      }
      case 3:
        writeFileAtomically(dir / "sweep" / "sweep.json", doc);
        fuzz::reseal(dir / "sweep", "sweep");
        readSpecularSweep(dir / "sweep");
        break;
      case 5:
        fs::create_directories(dir / "tune");
        writeFileAtomically(dir / "tune" / "tune.json", doc);
        sealOutputSet(dir / "tune", "tune", {"tune.json"});
        readTunedSettings(dir / "tune" / "tune.json");
        break;
      default:
        writeFileAtomically(dir / "encode" / "encode.json", doc);
        fuzz::reseal(dir / "encode", "encode");
        readShippedVolumes(dir / "encode", readGtsoInput(dir / "gtso"));
        break;
    }
  } catch (const Error&) {
  }
  return 0;
}
