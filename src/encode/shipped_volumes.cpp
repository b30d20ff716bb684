#include "encode/shipped_volumes.h"

#include "common/error.h"
#include "common/input_limits.h"
#include "common/output_set.h"
#include "encode/bc4_layout.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;

// A layout from encode.json's "layouts": {"3d": {"chosen": {"axis": [x, y, z]}}, ...}.
GtsoLayout readLayout(const nlohmann::json& j, const char* table, const std::string& where) {
  try {
    const auto& axis = j.at("layouts").at(table).at("chosen").at("axis");
    // Integers 0..2 as written: get<int>() would wrap 4294967296 to 0 (docs/limits.md §Values).
    for (int k = 0; k < 3; ++k) {
      if (!axis.at(k).is_number_integer() || axis.at(k).get<std::int64_t>() < 0 ||
          axis.at(k).get<std::int64_t>() > 2 || axis.size() != 3) {
        throw Error("not three table axes 0, 1, 2");
      }
    }
    GtsoLayout l{{axis.at(0).get<int>(), axis.at(1).get<int>(), axis.at(2).get<int>()}};
    int seen = 0;
    for (int k : l.axis) seen |= 1 << k;
    if (seen != 7) throw Error("not a permutation of the table axes");
    return l;
  } catch (const std::exception& e) {
    throw Error(where + ": no valid layouts/" + table + "/chosen/axis (" + e.what() + ")");
  }
}

// The theta_o tiles across x of the 4D volume: layouts/4d/packing/tiles_x, an integer in
// [1, N_w] (docs/export.md §2c).
int readTilesX(const nlohmann::json& j, const GtsoTable& t, const std::string& where) {
  try {
    const auto& n = j.at("layouts").at("4d").at("packing").at("tiles_x");
    if (!n.is_number_integer() || n.get<std::int64_t>() < 1 || n.get<std::int64_t>() > t.dims[3]) {
      throw Error("not an integer in [1, " + std::to_string(t.dims[3]) + "]");
    }
    return n.get<int>();
  } catch (const std::exception& e) {
    throw Error(where + ": no valid layouts/4d/packing/tiles_x (" + e.what() + ")");
  }
}

double bc4Number(const nlohmann::json& j, const char* table, const char* key,
                 const std::string& where) {
  try {
    return j.at("bc4").at(table).at(key).get<double>();
  } catch (const std::exception&) {
    throw Error(where + ": no number bc4/" + table + "/" + key);
  }
}

// One table's volumes, each checked for the format and extent of the table in its layout.
ShippedVolume readTable(const OutputManifest& set, const nlohmann::json& j, const GtsoTable& t,
                        const char* key, const std::string& base, const std::string& where) {
  ShippedVolume v;
  v.layout = readLayout(j, key, where);
  if (t.dims.size() == 4) v.layout.tilesX = readTilesX(j, t, where);
  v.layout_json = j["layouts"][key];
  v.volume = layoutVolume(t, v.layout);
  v.bc4_rmse = bc4Number(j, key, "rmse", where);
  v.bc4_max = bc4Number(j, key, "max_abs", where);
  v.bc4_seconds = bc4Number(j, key, "seconds", where);
  const std::pair<VolumeData*, TexelFormat> formats[3] = {
      {&v.bc4, TexelFormat::kBc4}, {&v.r16, TexelFormat::kR16}, {&v.r8, TexelFormat::kR8}};
  for (const auto& [data, format] : formats) {
    const std::string suffix =
        format == TexelFormat::kBc4 ? "" : std::string("_") + texelFormatName(format);
    const std::string name = base + suffix + ".dds";
    *data = parseDds(set.readVerified(name), (set.dir / name).string());
    if (data->format != format || data->width != v.volume[0] || data->height != v.volume[1] ||
        data->depth != v.volume[2]) {
      throw Error((set.dir / name).string() + ": not the " + texelFormatName(format) +
                  " volume of " + t.file + " in its layout; rerun `gtbake encode`");
    }
  }
  return v;
}

}  // namespace

std::string gtsoTableHash(const fs::path& gtso_dir, const std::string& file) {
  const OutputManifest gtso = readOutputSet(gtso_dir, "gtso");
  const OutputFile* f = gtso.find(file);
  if (f == nullptr) throw Error((gtso_dir / file).string() + ": not in gtso.manifest.json");
  return f->sha256;
}

ShippedVolumes readShippedVolumes(const fs::path& dir, const GtsoInput& gtso) {
  const OutputManifest set = readOutputSet(dir, "encode");
  const std::string where = (dir / "encode.json").string();
  ShippedVolumes out;
  out.json = parseJsonText(set.readVerified("encode.json"), where);
  // The volumes must come from exactly these tables: gtso.manifest.json's hashes.
  const fs::path gtso_dir = gtso.json_dir;
  for (const GtsoTable* t : {&gtso.table3d, &gtso.table4d}) {
    const std::string key = t == &gtso.table3d ? "gtso3d.f32" : "gtso4d.f32";
    const auto& inputs = out.json.contains("inputs") ? out.json["inputs"] : nlohmann::json();
    if (!inputs.contains(key) || inputs[key] != gtsoTableHash(gtso_dir, t->file)) {
      throw Error(where + ": encoded from other tables than " + (gtso_dir / t->file).string() +
                  "; rerun `gtbake encode`");
    }
  }
  out.t3 = readTable(set, out.json, gtso.table3d, "3d", "gtso3d", where);
  out.t4 = readTable(set, out.json, gtso.table4d, "4d", "gtso4d", where);
  return out;
}

}  // namespace gtbake
