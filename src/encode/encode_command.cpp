#include "encode/encode_command.h"

#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_lock.h"
#include "common/output_set.h"
#include "common/threads.h"
#include "encode/bc4_layout.h"
#include "encode/format_errors.h"
#include "encode/shipped_volumes.h"
#include "gtbake_version.h"
#include "gtso/gtso_set.h"
#include "texture/texture_containers.h"

namespace gtbake {
namespace {

// A forced layout from the options ({x, y, z} table axes), or none.
std::optional<GtsoLayout> forcedLayout(const std::vector<int>& axes) {
  if (axes.empty()) return std::nullopt;
  if (axes.size() != 3) throw Error("encode: a forced layout names 3 table axes");
  return GtsoLayout{{axes[0], axes[1], axes[2]}};
}

// gtso3d{,_r16,_r8}.{dds,ktx2} of one table: BC4 from the exact encoder, R16 / R8 quantised,
// all in the chosen layout.
void addVolumes(OutputSet& output, const std::string& base, const LayoutChoice& c,
                const std::string& writer) {
  const auto& s = c.volume;
  const std::vector<std::uint8_t> r16 =
      quantizeUnorm(c.texels.data(), c.texels.size(), TexelFormat::kR16);
  const std::vector<std::uint8_t> r8 =
      quantizeUnorm(c.texels.data(), c.texels.size(), TexelFormat::kR8);
  const VolumeImage images[3] = {{s[0], s[1], s[2], &c.bc4.bytes, TexelFormat::kBc4},
                                 {s[0], s[1], s[2], &r16, TexelFormat::kR16},
                                 {s[0], s[1], s[2], &r8, TexelFormat::kR8}};
  const char* suffix[3] = {"", "_r16", "_r8"};
  for (int k = 0; k < 3; ++k) {
    output.add(base + suffix[k] + ".dds", makeDds(images[k]));
    output.add(base + suffix[k] + ".ktx2", makeKtx2(images[k], writer));
  }
}

nlohmann::ordered_json encodeJson(const EncodeOptions& options, const GtsoInput& gtso,
                                  const GtsoLayouts& layouts, const nlohmann::json& end_to_end) {
  nlohmann::ordered_json j;
  j["gtbake_version"] = GTBAKE_VERSION;
  j["inputs"] = {{"gtso3d.f32", gtsoTableHash(options.gtso, gtso.table3d.file)},
                 {"gtso4d.f32", gtsoTableHash(options.gtso, gtso.table4d.file)}};
  j["layouts"] = {{"3d", layouts.t3.json}, {"4d", layouts.t4.json}};
  j["layout_note"] =
      "texture x, y, z hold the named table axes (4D: theta_o slice w is the tile at texel "
      "(N_x (w mod tiles_x), 0, N_z floor(w / tiles_x)), layouts/4d/packing); BC4 blocks are 4x4 "
      "over (x, y); gtso3d*/gtso4d* files of every format use this layout and the generated "
      "header/includes read it (kGtso3DLayout, kGtso4DLayout, GTSO_3D_LAYOUT, kGtso4DTilesX)";
  for (const auto& [key, c] : {std::pair{"3d", &layouts.t3}, std::pair{"4d", &layouts.t4}}) {
    j["bc4"][key] = {
        {"rmse", c->bc4.rmse}, {"max_abs", c->bc4.max_abs}, {"seconds", c->bc4.seconds}};
  }
  j["end_to_end"] = end_to_end;
  return j;
}

// ", atlas 4x8 tiles" for the 4D choice's packing.
std::string packingText(const nlohmann::json& choice) {
  const nlohmann::json& p = choice["packing"];
  return ", " + p["name"].get<std::string>() + " " + std::to_string(p["tiles_x"].get<int>()) + "x" +
         std::to_string(p["tiles_z"].get<int>()) + " tiles";
}

void printSummary(const EncodeOptions& options, const GtsoInput& gtso, const GtsoLayouts& l,
                  const nlohmann::json& end_to_end, int threads, double seconds) {
  std::FILE* out = options.summary;
  if (out == nullptr) return;
  std::fprintf(out, "gtbake encode: %s (threads: %d)\n", options.out.string().c_str(), threads);
  std::fprintf(out, "  table  volume         layout  BC4 RMSE    BC4 max     encode\n");
  const std::pair<const GtsoTable*, const LayoutChoice*> rows[] = {{&gtso.table3d, &l.t3},
                                                                   {&gtso.table4d, &l.t4}};
  for (const auto& [table, c] : rows) {
    const std::string extent = std::to_string(c->volume[0]) + "x" + std::to_string(c->volume[1]) +
                               "x" + std::to_string(c->volume[2]);
    std::fprintf(out, "  %-5s  %-13s  %-6s  %.4e  %.4e  %.2f s%s\n",
                 table == &gtso.table3d ? "3D" : "4D", extent.c_str(),
                 layoutSwizzle(c->layout).c_str(), c->bc4.rmse, c->bc4.max_abs, c->bc4.seconds,
                 table == &gtso.table3d ? "" : packingText(c->json).c_str());
    for (const LayoutCandidate& k : c->candidates) {
      std::fprintf(out,
                   "         candidate %s: end-to-end uniform RMS %.5f max %.4f, stress max %.4f\n",
                   layoutSwizzle(k.layout).c_str(), k.uniform_rms, k.uniform_max, k.stress_max);
    }
  }
  for (const char* key : {"3d", "4d"}) {
    const nlohmann::json& t = end_to_end[key];
    std::fprintf(out, "  %s as shipped, end to end (max over 2 seeds / mean RMS):", key);
    for (const auto& [format, e] : t["formats"].items()) {
      std::fprintf(out, " %s %.4f/%.5f", format.c_str(), e["uniform"]["max"].get<double>(),
                   e["uniform"]["rms"].get<double>());
    }
    std::fprintf(out, "; recommended %s\n", t["recommended"].get<std::string>().c_str());
  }
  std::fprintf(out, "  wrote gtso{3d,4d}{,_r16,_r8}.{dds,ktx2}, encode.json in %.2f s\n", seconds);
}

}  // namespace

EncodeResult runEncode(const EncodeOptions& options) {
  if (options.gtso.empty()) throw Error("encode: --gtso DIR is required");
  if (options.out.empty()) throw Error("encode: --out DIR is required");
  const OutputLock lock(options.out);  // for the whole run (output_lock.h)
  const auto start = std::chrono::steady_clock::now();
  const GtsoInput gtso = readGtsoInput(options.gtso);
  const ThreadLimit limit(options.threads);
  // Each table's texture layout, chosen with the real encoder end to end (bc4_layout.h); every
  // format of a table is written in it.
  const auto f3 = forcedLayout(options.force_layout_3d);
  const auto f4 = forcedLayout(options.force_layout_4d);
  // Every 4D candidate must fit the packing (before the encoder runs).
  for (const GtsoLayout& l : layoutCandidates(gtso.table4d)) {
    tilesAcrossX(gtso.table4d, l, options.layout_4d, options.atlas_max_extent);
  }
  GtsoLayouts layouts = chooseLayouts(gtso, options.layout_lobes, f3 ? &*f3 : nullptr,
                                      f4 ? &*f4 : nullptr, options.progress);
  // The choice is made on the fold; the lookup reads the same blocks packed either way to the
  // last bit (gtso4DLookup), so the packing only reorders them.
  packLayoutChoice(gtso.table4d, options.layout_4d, options.atlas_max_extent, &layouts.t4);
  const nlohmann::json end_to_end = endToEndJson(gtso, layouts, options.progress);
  const std::string writer = std::string("gtbake ") + GTBAKE_VERSION;
  OutputSet output(options.out, "encode");  // 12 volumes + encode.json, committed as one set
  addVolumes(output, "gtso3d", layouts.t3, writer);
  addVolumes(output, "gtso4d", layouts.t4, writer);
  output.add("encode.json", encodeJson(options, gtso, layouts, end_to_end).dump(2) + "\n");
  output.setSettings({{"gtso", relativePath(options.gtso, options.out)}});
  output.commit();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  printSummary(options, gtso, layouts, end_to_end, limit.threads(), seconds);
  return {layouts.t3.bc4.rmse, layouts.t3.bc4.max_abs, layouts.t4.bc4.rmse, layouts.t4.bc4.max_abs,
          seconds};
}

}  // namespace gtbake
