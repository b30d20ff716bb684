#include "gtso/gtso_set.h"

#include <cmath>
#include <cstring>

#include "common/checked_math.h"
#include "common/error.h"
#include "common/input_limits.h"
#include "common/output_set.h"
#include "common/text_escape.h"
#include "runtime/gtso_runtime.h"

namespace gtbake {
namespace {

constexpr const char* kAxisNames[4] = {"x", "y", "z", "w"};
constexpr int kMaxAxisTexels = 4096;  // far beyond any table gtbake bakes; rejects garbage dims

GtsoTable readTable(const OutputManifest& set, const nlohmann::json& tables, const std::string& key,
                    int rank) {
  const std::filesystem::path& dir = set.dir;
  const std::string where = (dir / "gtso.json").string() + " tables." + key;
  const nlohmann::json& t = jsonMember(tables, key, (dir / "gtso.json").string() + " tables");
  GtsoTable table;
  table.meta = t;
  const nlohmann::json& file = jsonMember(t, "file", where);
  if (!file.is_string()) throw Error(where + ": \"file\" must be a string");
  table.file = file.get<std::string>();
  // The name reaches the generated code's comments: only a plain file name (docs/limits.md
  // §Names in outputs).
  if (fileSlug(table.file) != table.file) {
    throw Error(where + ": \"file\" must be a plain file name of [A-Za-z0-9_.-], got " +
                file.dump());
  }
  const nlohmann::json& dims = jsonMember(t, "dims", where);
  if (!dims.is_array() || static_cast<int>(dims.size()) != rank) {
    throw Error(where + ": \"dims\" must list " + std::to_string(rank) + " sizes");
  }
  for (const auto& d : dims) {
    if (!d.is_number_integer() || d.get<std::int64_t>() < 2 ||
        d.get<std::int64_t>() > kMaxAxisTexels) {
      throw Error(where + ": every entry of \"dims\" must be an integer in [2, 4096]");
    }
    table.dims.push_back(d.get<int>());
  }
  if (table.dims[0] % 4 != 0 || table.dims[1] % 4 != 0) {
    throw Error(where + ": x and y sizes must be multiples of 4 for BC4 blocks");
  }
  const nlohmann::json& axes = jsonMember(t, "axes", where);
  if (!axes.is_array() || static_cast<int>(axes.size()) != rank) {
    throw Error(where + ": \"axes\" must list " + std::to_string(rank) + " axes");
  }
  const GtsoAxisInfo* const* expected = rank == 3 ? kGtso3DAxisInfo : kGtso4DAxisInfo;
  for (int i = 0; i < rank; ++i) {
    const nlohmann::json& a = axes[i];
    const nlohmann::json& name = jsonMember(a, "axis", where + ".axes");
    const nlohmann::json& quantity = jsonMember(a, "quantity", where + ".axes");
    if (!name.is_string() || name.get<std::string>() != kAxisNames[i]) {
      throw Error(where + ": axis " + std::to_string(i) + " must be named \"" + kAxisNames[i] +
                  "\"");
    }
    if (!quantity.is_string() || quantity.get<std::string>() != expected[i]->quantity) {
      throw Error(where + ": axis " + kAxisNames[i] + " has quantity " + quantity.dump() +
                  ", the runtime lookup expects \"" + expected[i]->quantity + "\"");
    }
    table.axes.push_back({kAxisNames[i], quantity.get<std::string>()});
  }
  table.volume = {table.dims[0], table.dims[1],
                  rank == 4 ? table.dims[2] * table.dims[3] : table.dims[2]};
  const std::size_t count =
      checkedMul(checkedMul(static_cast<std::uint64_t>(table.volume[0]), table.volume[1], where),
                 static_cast<std::uint64_t>(table.volume[2]), where);
  checkLimit(kMaxInputBytes, checkedMul(count, sizeof(float), where), where);
  fileInsideDirectory(dir, table.file, where);
  const std::string bytes = set.readVerified(table.file);
  if (bytes.size() != count * sizeof(float)) {
    throw Error((dir / table.file).string() + ": " + std::to_string(bytes.size()) +
                " bytes, expected " + std::to_string(count * sizeof(float)) +
                " (float32 little-endian, dims from gtso.json)");
  }
  table.values.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t bits = 0;
    for (int b = 0; b < 4; ++b) {
      bits |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[4 * i + b])) << (8 * b);
    }
    std::memcpy(&table.values[i], &bits, sizeof(float));
    if (!std::isfinite(table.values[i])) {
      throw Error((dir / table.file).string() + ": texel " + std::to_string(i) +
                  " is not a finite number");
    }
  }
  return table;
}

// The axis constants the tables were baked with must be the runtime's.
void checkAxisConstants(const nlohmann::json& j, const std::string& where) {
  const nlohmann::json& c = jsonMember(j, "axis_constants", where);
  for (const auto& [key, macro, value] : kGtsoAxisConstants) {
    if (shippedNumber(c, key, where + " axis_constants") != value) {
      throw Error(where + ": axis_constants." + key +
                  " differs from this gtbake's runtime lookup (" + std::to_string(value) +
                  "); re-run `gtbake gtso`");
    }
  }
}

}  // namespace

GtsoInput readGtsoInput(const std::filesystem::path& dir) {
  if (!std::filesystem::is_directory(dir)) {
    throw Error("--gtso " + dir.string() + ": not a directory (run `gtbake gtso --out DIR`)");
  }
  GtsoInput in;
  const OutputManifest set = readOutputSet(dir, "gtso");
  in.json = set.readVerifiedJson("gtso.json");
  in.json_dir = dir;
  const std::string where = (dir / "gtso.json").string();
  checkAxisConstants(in.json, where);
  const nlohmann::json& tables = jsonMember(in.json, "tables", where);
  in.table3d = readTable(set, tables, "3d", 3);
  in.table4d = readTable(set, tables, "4d", 4);
  const nlohmann::json& cone = jsonMember(in.json, "cone", where);
  in.u = shippedNumber(cone, "u", where + " cone");
  in.u_se = shippedNumber(cone, "u_se", where + " cone", true);
  if (!(in.u > 0.0 && in.u < 1.0)) throw Error(where + ": cone.u must lie in (0, 1)");
  const nlohmann::json& closedForm = jsonMember(in.json, "closed_form", where);
  const nlohmann::json& coeffs = jsonMember(closedForm, "coefficients", where + " closed_form");
  if (!coeffs.is_array() || coeffs.size() != static_cast<std::size_t>(kGtsoS3ClosedFormCoeffs)) {
    throw Error(where + ": closed_form.coefficients must list " +
                std::to_string(kGtsoS3ClosedFormCoeffs) +
                " numbers (the form of this gtbake's runtime); re-run `gtbake gtso`");
  }
  for (const auto& c : coeffs) {
    if (!c.is_number() || !(std::abs(c.get<double>()) <= kMaxShippedMagnitude)) {
      throw Error(where +
                  ": closed_form.coefficients must be finite numbers of magnitude at most " +
                  std::to_string(static_cast<int>(kMaxShippedMagnitude)));
    }
    in.s3_closed_form.push_back(c.get<double>());
  }
  return in;
}

}  // namespace gtbake
