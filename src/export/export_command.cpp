// `gtbake export` (SPEC §1.5, §2): fit.json + the gtso directory -> BC4 DDS/KTX2 volumes, the C++
// header and the HLSL/GLSL includes. Everything is built in memory first, then each file is
// written atomically (temporary name + rename), so a failure never leaves a partial file.
#include "export/export_command.h"

#include <chrono>
#include <cstdio>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/progress.h"
#include "common/threads.h"
#include "export/bc4_encoder.h"
#include "export/export_inputs.h"
#include "export/generated_code.h"
#include "export/texture_containers.h"
#include "gtbake_version.h"

namespace gtbake {
namespace {

std::size_t outsideUnitInterval(const std::vector<float>& values) {
  std::size_t n = 0;
  for (float v : values) n += (v < 0.0f || v > 1.0f) ? 1 : 0;
  return n;
}

Bc4Volume encodeTable(const Bc4Encoder& encoder, const GtsoTable& table, const char* label,
                      bool progress) {
  const auto& s = table.volume;
  Progress bar(label, static_cast<std::uint64_t>(s[0] / 4) * (s[1] / 4) * s[2], progress);
  Bc4Volume v = encodeBc4Volume(encoder, table.values.data(), s[0], s[1], s[2], &bar);
  bar.finish();
  return v;
}

}  // namespace

ExportResult runExport(const ExportOptions& options) {
  if (options.fit.empty()) throw Error("export: --fit FILE.json is required");
  if (options.gtso.empty()) throw Error("export: --gtso DIR is required");
  if (options.out.empty()) throw Error("export: --out DIR is required");
  const auto start = std::chrono::steady_clock::now();
  const FitInput fit = readFitInput(options.fit);
  GtsoInput gtso = readGtsoInput(options.gtso);
  if (!options.validate_gtso.empty()) applyValidateGtsoU(options.validate_gtso, &gtso);

  const ThreadLimit limit(options.threads);
  const Bc4Encoder encoder;
  const Bc4Volume bc4_3d = encodeTable(encoder, gtso.table3d, "BC4 3D table", options.progress);
  const Bc4Volume bc4_4d = encodeTable(encoder, gtso.table4d, "BC4 4D table", options.progress);

  GeneratedCodeInput code;
  code.fit = &fit;
  code.gtso = &gtso;
  code.bc4_3d = &bc4_3d;
  code.bc4_4d = &bc4_4d;
  code.command_line = options.command_line.empty() ? "gtbake export" : options.command_line;
  code.version = GTBAKE_VERSION;
  const std::string writer = "gtbake " + code.version;
  const auto& s3 = gtso.table3d.volume;
  const auto& s4 = gtso.table4d.volume;
  const Bc4VolumeImage image3{s3[0], s3[1], s3[2], &bc4_3d.bytes};
  const Bc4VolumeImage image4{s4[0], s4[1], s4[2], &bc4_4d.bytes};
  const std::pair<const char*, std::string> files[] = {
      {"gtso3d.dds", makeDds(image3)},
      {"gtso3d.ktx2", makeKtx2(image3, writer)},
      {"gtso4d.dds", makeDds(image4)},
      {"gtso4d.ktx2", makeKtx2(image4, writer)},
      {"gtbake_tables.h", makeTablesHeader(code)},
      {"gtbake_tables.hlsl", makeShaderInclude(code, ShaderLanguage::kHlsl)},
      {"gtbake_tables.glsl", makeShaderInclude(code, ShaderLanguage::kGlsl)},
  };
  ensureDirectory(options.out);
  for (const auto& [name, bytes] : files) writeFileAtomically(options.out / name, bytes);

  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("gtbake export: %s (threads: %d)\n", options.out.string().c_str(), limit.threads());
  std::printf("  table  volume         BC4 RMSE    BC4 max     clamped  encode\n");
  const std::pair<const GtsoTable*, const Bc4Volume*> rows[] = {{&gtso.table3d, &bc4_3d},
                                                                {&gtso.table4d, &bc4_4d}};
  for (const auto& [table, v] : rows) {
    const std::string extent = std::to_string(table->volume[0]) + "x" +
                               std::to_string(table->volume[1]) + "x" +
                               std::to_string(table->volume[2]);
    std::printf("  %-5s  %-13s  %.4e  %.4e  %7zu  %.2f s\n", table == &gtso.table3d ? "3D" : "4D",
                extent.c_str(), v->rmse, v->max_abs, outsideUnitInterval(table->values),
                v->seconds);
  }
  std::printf("  wrote gtbake_tables.h/.hlsl/.glsl, gtso3d.dds/.ktx2, gtso4d.dds/.ktx2 in %.2f s\n",
              seconds);
  return {bc4_3d.rmse, bc4_3d.max_abs, bc4_4d.rmse, bc4_4d.max_abs};
}

}  // namespace gtbake
