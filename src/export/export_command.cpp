// `gtbake export` (SPEC §1.5, §2): fit.json + the gtso directory -> BC4 DDS/KTX2 volumes, the C++
// header and the HLSL/GLSL includes. Everything is built in memory first, then each file is
// written atomically (temporary name + rename), so a failure never leaves a partial file.
#include "export/export_command.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_set.h"
#include "common/progress.h"
#include "common/threads.h"
#include "export/bc4_encoder.h"
#include "export/bc4_layout.h"
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

// A forced layout from the options ({x, y, z} table axes), or none.
std::optional<GtsoLayout> forcedLayout(const std::vector<int>& axes) {
  if (axes.empty()) return std::nullopt;
  if (axes.size() != 3) throw Error("export: a forced layout names 3 table axes");
  return GtsoLayout{{axes[0], axes[1], axes[2]}};
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
  // Each table's texture layout, chosen with the real encoder end to end (bc4_layout.h); every
  // format of a table is written in it.
  std::shared_ptr<const GtsoLayouts> layouts = options.layouts;
  if (!layouts) {
    const auto f3 = forcedLayout(options.force_layout_3d);
    const auto f4 = forcedLayout(options.force_layout_4d);
    layouts = std::make_shared<const GtsoLayouts>(chooseLayouts(
        gtso, options.layout_lobes, f3 ? &*f3 : nullptr, f4 ? &*f4 : nullptr, options.progress));
  }
  const LayoutChoice& layout3 = layouts->t3;
  const LayoutChoice& layout4 = layouts->t4;
  if (permuteToLayout(gtso.table3d, layout3.layout) != layout3.texels ||
      permuteToLayout(gtso.table4d, layout4.layout) != layout4.texels) {
    throw Error("export: the given BC4 layouts were chosen for other tables than " +
                options.gtso.string());
  }
  const Bc4Volume& bc4_3d = layout3.bc4;
  const Bc4Volume& bc4_4d = layout4.bc4;

  GeneratedCodeInput code;
  code.fit = &fit;
  code.gtso = &gtso;
  code.bc4_3d = &bc4_3d;
  code.bc4_4d = &bc4_4d;
  code.layout_3d = layout3.layout;
  code.layout_4d = layout4.layout;
  code.volume_3d = layout3.volume;
  code.volume_4d = layout4.volume;
  code.embedded_3d = &layout3.candidates[static_cast<std::size_t>(layout3.chosen)];
  code.embedded_4d = &layout4.candidates[static_cast<std::size_t>(layout4.chosen)];
  code.command_line = options.command_line.empty() ? "gtbake export" : options.command_line;
  code.version = GTBAKE_VERSION;
  const std::string writer = "gtbake " + code.version;
  // BC4 from the exact encoder, R16 / R8 quantised; each in DDS and KTX2, in the chosen layout.
  std::vector<std::pair<std::string, std::string>> files;
  const std::pair<const char*, const LayoutChoice*> tables[] = {{"gtso3d", &layout3},
                                                                {"gtso4d", &layout4}};
  std::vector<std::uint8_t> r16[2], r8[2];
  for (int t = 0; t < 2; ++t) {
    const LayoutChoice& c = *tables[t].second;
    const auto& s = c.volume;
    r16[t] = quantizeUnorm(c.texels.data(), c.texels.size(), VolumeFormat::kR16);
    r8[t] = quantizeUnorm(c.texels.data(), c.texels.size(), VolumeFormat::kR8);
    const std::string base = tables[t].first;
    const VolumeImage images[3] = {{s[0], s[1], s[2], &c.bc4.bytes, VolumeFormat::kBc4},
                                   {s[0], s[1], s[2], &r16[t], VolumeFormat::kR16},
                                   {s[0], s[1], s[2], &r8[t], VolumeFormat::kR8}};
    const char* suffix[3] = {"", "_r16", "_r8"};
    for (int k = 0; k < 3; ++k) {
      files.emplace_back(base + suffix[k] + ".dds", makeDds(images[k]));
      files.emplace_back(base + suffix[k] + ".ktx2", makeKtx2(images[k], writer));
    }
  }
  nlohmann::ordered_json ej;
  ej["gtbake_version"] = code.version;
  ej["layouts"] = {{"3d", layout3.json}, {"4d", layout4.json}};
  ej["layout_note"] =
      "texture x, y, z hold the named table axes (4D: theta_o folds into the depth, z' = w*N_z + "
      "z); BC4 blocks are 4x4 over (x, y); gtso3d*/gtso4d* files of every format use this layout "
      "and the generated header/includes read it (kGtso3DLayout, GTSO_3D_LAYOUT)";
  files.emplace_back("export.json", ej.dump(2) + "\n");
  files.emplace_back("gtbake_tables.h", makeTablesHeader(code));
  files.emplace_back("gtbake_tables.hlsl", makeShaderInclude(code, ShaderLanguage::kHlsl));
  files.emplace_back("gtbake_tables.glsl", makeShaderInclude(code, ShaderLanguage::kGlsl));
  OutputSet output(options.out, "export");  // all 16 files are committed as one set
  for (const auto& [name, bytes] : files) output.add(name, bytes);
  output.setSettings({{"fit", relativePath(options.fit, options.out)},
                      {"gtso", relativePath(options.gtso, options.out)}});
  output.commit();

  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("gtbake export: %s (threads: %d)\n", options.out.string().c_str(), limit.threads());
  std::printf("  table  volume         layout  BC4 RMSE    BC4 max     clamped  encode\n");
  const std::pair<const GtsoTable*, const LayoutChoice*> rows[] = {{&gtso.table3d, &layout3},
                                                                   {&gtso.table4d, &layout4}};
  for (const auto& [table, c] : rows) {
    const std::string extent = std::to_string(c->volume[0]) + "x" + std::to_string(c->volume[1]) +
                               "x" + std::to_string(c->volume[2]);
    std::printf("  %-5s  %-13s  %-6s  %.4e  %.4e  %7zu  %.2f s\n",
                table == &gtso.table3d ? "3D" : "4D", extent.c_str(),
                layoutSwizzle(c->layout).c_str(), c->bc4.rmse, c->bc4.max_abs,
                outsideUnitInterval(table->values), c->bc4.seconds);
    for (const LayoutCandidate& k : c->candidates) {
      std::printf("         candidate %s: end-to-end uniform RMS %.5f max %.4f, stress max %.4f\n",
                  layoutSwizzle(k.layout).c_str(), k.uniform_rms, k.uniform_max, k.stress_max);
    }
  }
  std::printf(
      "  wrote gtbake_tables.h/.hlsl/.glsl, gtso{3d,4d}{,_r16,_r8}.{dds,ktx2}, export.json in "
      "%.2f s\n",
      seconds);
  return {bc4_3d.rmse, bc4_3d.max_abs, bc4_4d.rmse, bc4_4d.max_abs};
}

}  // namespace gtbake
