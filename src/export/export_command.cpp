// `gtbake export` (SPEC §1.5, §2): fit.json + the gtso directory -> BC4 DDS/KTX2 volumes, the C++
// header and the HLSL/GLSL includes. Everything is built in memory first, then each file is
// written atomically (temporary name + rename), so a failure never leaves a partial file.
#include "export/export_command.h"

#include <chrono>
#include <cstdio>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_set.h"
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
  // BC4 from the exact encoder, R16 / R8 quantised; each in DDS and KTX2.
  std::vector<std::pair<std::string, std::string>> files;
  const std::pair<const char*, const GtsoTable*> tables[] = {{"gtso3d", &gtso.table3d},
                                                             {"gtso4d", &gtso.table4d}};
  std::vector<std::uint8_t> r16[2], r8[2];
  for (int t = 0; t < 2; ++t) {
    const GtsoTable& table = *tables[t].second;
    const auto& s = table.volume;
    r16[t] = quantizeUnorm(table.values.data(), table.values.size(), VolumeFormat::kR16);
    r8[t] = quantizeUnorm(table.values.data(), table.values.size(), VolumeFormat::kR8);
    const std::string base = tables[t].first;
    const VolumeImage images[3] = {
        {s[0], s[1], s[2], t == 0 ? &bc4_3d.bytes : &bc4_4d.bytes, VolumeFormat::kBc4},
        {s[0], s[1], s[2], &r16[t], VolumeFormat::kR16},
        {s[0], s[1], s[2], &r8[t], VolumeFormat::kR8}};
    const char* suffix[3] = {"", "_r16", "_r8"};
    for (int k = 0; k < 3; ++k) {
      files.emplace_back(base + suffix[k] + ".dds", makeDds(images[k]));
      files.emplace_back(base + suffix[k] + ".ktx2", makeKtx2(images[k], writer));
    }
  }
  files.emplace_back("gtbake_tables.h", makeTablesHeader(code));
  files.emplace_back("gtbake_tables.hlsl", makeShaderInclude(code, ShaderLanguage::kHlsl));
  files.emplace_back("gtbake_tables.glsl", makeShaderInclude(code, ShaderLanguage::kGlsl));
  OutputSet output(options.out, "export");  // all 15 files are committed as one set
  for (const auto& [name, bytes] : files) output.add(name, bytes);
  output.setSettings({{"fit", relativePath(options.fit, options.out)},
                      {"gtso", relativePath(options.gtso, options.out)}});
  output.commit();

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
  std::printf("  wrote gtbake_tables.h/.hlsl/.glsl, gtso{3d,4d}{,_r16,_r8}.{dds,ktx2} in %.2f s\n",
              seconds);
  return {bc4_3d.rmse, bc4_3d.max_abs, bc4_4d.rmse, bc4_4d.max_abs};
}

}  // namespace gtbake
