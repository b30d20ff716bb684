// `gtbake export` (docs/export.md): fit.json, the gtso directory and the volumes of `gtbake encode`
// -> the C++ header and the HLSL/GLSL includes. Everything is built in memory first, then the set
// is committed atomically, so a failure never leaves a partial file.
#include "export/export_command.h"

#include <chrono>
#include <cstdio>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_lock.h"
#include "common/output_set.h"
#include "encode/bc4_layout.h"
#include "encode/shipped_volumes.h"
#include "export/generated_code.h"
#include "fit/fit_set.h"
#include "gtbake_version.h"
#include "tune/tune_set.h"
#include "validate_gtso/validate_gtso_set.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

std::size_t outsideUnitInterval(const std::vector<float>& values) {
  std::size_t n = 0;
  for (float v : values) n += (v < 0.0f || v > 1.0f) ? 1 : 0;
  return n;
}

// The BC4 volume of a table as the header embeds it: encode's blocks and errors.
Bc4Volume bc4Of(const ShippedVolume& v) {
  Bc4Volume b;
  b.bytes = v.bc4.bytes;
  b.rmse = v.bc4_rmse;
  b.max_abs = v.bc4_max;
  b.seconds = v.bc4_seconds;
  return b;
}

void printSummary(const ExportOptions& options, const GtsoInput& gtso, const ShippedVolumes& sv,
                  double seconds) {
  std::printf("gtbake export: %s\n", options.out.string().c_str());
  std::printf("  table  volume         layout  BC4 RMSE    BC4 max     clamped\n");
  const std::pair<const GtsoTable*, const ShippedVolume*> rows[] = {{&gtso.table3d, &sv.t3},
                                                                    {&gtso.table4d, &sv.t4}};
  for (const auto& [table, v] : rows) {
    const std::string extent = std::to_string(v->volume[0]) + "x" + std::to_string(v->volume[1]) +
                               "x" + std::to_string(v->volume[2]);
    std::printf("  %-5s  %-13s  %-6s  %.4e  %.4e  %7zu\n", table == &gtso.table3d ? "3D" : "4D",
                extent.c_str(), layoutSwizzle(v->layout).c_str(), v->bc4_rmse, v->bc4_max,
                outsideUnitInterval(table->values));
  }
  std::printf("  wrote gtbake_tables.h/.hlsl/.glsl in %.2f s\n", seconds);
}

// What each shipped file is, README.md of the export set (docs/export.md lists the same).
std::string shipReadme(bool volumes_here) {
  std::string text =
      "# gtbake tables\n\n"
      "What an engine ships, written by `gtbake export` (docs/export.md):\n\n"
      "- `gtbake_tables.h`: C++ constants (Equation 10, the engine profiles, the cone's u), the\n"
      "  BC4 blocks of both GTSO tables and the runtime lookups.\n"
      "- `gtbake_tables.hlsl`, `gtbake_tables.glsl`: the same constants and lookups as shader\n"
      "  includes, reading the volumes below.\n";
  if (volumes_here) {
    text +=
        "- `gtso3d.dds`, `gtso3d.ktx2`: the 3D table S3 as a BC4_UNORM volume.\n"
        "- `gtso4d.dds`, `gtso4d.ktx2`: the 4D table S4 as a BC4_UNORM volume (its layout in\n"
        "  `gtbake_tables.h`).\n"
        "- `gtso3d_r16.*`, `gtso4d_r16.*`: the same volumes as R16_UNORM.\n"
        "- `gtso3d_r8.*`, `gtso4d_r8.*`: the same volumes as R8_UNORM.\n";
  }
  return text + "- `export.manifest.json`: the size and SHA-256 of every file here.\n";
}

// The volumes of `gtbake encode`, verified against its manifest and copied beside the header when
// encode wrote them into another directory (ship/ of `gtbake all`), and README.md.
void addShippedFiles(const fs::path& encode_dir, const fs::path& out, OutputSet& output) {
  const bool elsewhere = realOutputDirectory(encode_dir) != realOutputDirectory(out);
  if (elsewhere) {
    const OutputManifest set = readOutputSet(encode_dir, "encode");
    for (const OutputFile& f : set.files) {
      const std::string ext = fs::path(f.name).extension().string();
      if (ext == ".dds" || ext == ".ktx2") output.add(f.name, set.readVerified(f.name));
    }
  }
  output.add("README.md", shipReadme(elsewhere));
}

}  // namespace

ExportResult runExport(const ExportOptions& options) {
  if (options.fit.empty()) throw Error("export: --fit FILE.json is required");
  if (options.gtso.empty()) throw Error("export: --gtso DIR is required");
  if (options.out.empty()) throw Error("export: --out DIR is required");
  const OutputLock lock(options.out);  // for the whole run (output_lock.h)
  const auto start = std::chrono::steady_clock::now();
  const FitInput fit = readFitInput(options.fit);
  GtsoInput gtso = readGtsoInput(options.gtso);
  if (!options.validate_gtso.empty()) applyValidateGtsoU(options.validate_gtso, &gtso);
  const std::vector<ProfileInput> profiles =
      options.profiles.empty() ? std::vector<ProfileInput>{} : readProfiles(options.profiles);
  const std::vector<TunedSettingInput> tuned =
      options.tune.empty() ? std::vector<TunedSettingInput>{} : readTunedSettings(options.tune);
  // The volumes `gtbake encode` wrote for these tables (their layouts and BC4 blocks).
  const fs::path encode_dir = options.encode.empty() ? options.out : options.encode;
  const ShippedVolumes volumes = readShippedVolumes(encode_dir, gtso);
  const Bc4Volume bc4_3d = bc4Of(volumes.t3), bc4_4d = bc4Of(volumes.t4);

  GeneratedCodeInput code;
  code.fit = &fit;
  code.gtso = &gtso;
  code.bc4_3d = &bc4_3d;
  code.bc4_4d = &bc4_4d;
  code.profiles = &profiles;
  code.tuned = &tuned;
  code.layout_3d = volumes.t3.layout;
  code.layout_4d = volumes.t4.layout;
  code.volume_3d = volumes.t3.volume;
  code.volume_4d = volumes.t4.volume;
  code.end_to_end = volumes.json.contains("end_to_end") ? volumes.json["end_to_end"] : nullptr;
  code.command_line = options.command_line.empty() ? "gtbake export" : options.command_line;
  code.version = GTBAKE_VERSION;
  OutputSet output(options.out, "export");  // the header and the includes, committed as one set
  output.add("gtbake_tables.h", makeTablesHeader(code));
  output.add("gtbake_tables.hlsl", makeShaderInclude(code, ShaderLanguage::kHlsl));
  output.add("gtbake_tables.glsl", makeShaderInclude(code, ShaderLanguage::kGlsl));
  addShippedFiles(encode_dir, options.out, output);
  nlohmann::ordered_json settings = {{"fit", relativePath(options.fit, options.out)},
                                     {"gtso", relativePath(options.gtso, options.out)}};
  if (!options.profiles.empty()) settings["profiles"] = relativePath(options.profiles, options.out);
  if (!options.tune.empty()) settings["tune"] = relativePath(options.tune, options.out);
  output.setSettings(settings);
  output.commit();

  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  printSummary(options, gtso, volumes, seconds);
  return {bc4_3d.rmse, bc4_3d.max_abs, bc4_4d.rmse, bc4_4d.max_abs};
}

}  // namespace gtbake
