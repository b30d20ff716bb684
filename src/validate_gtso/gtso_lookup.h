// What the runtime reads from the shipped GTSO tables, behind one thin interface.
//
// validate-gtso scores S₃ and S₄ exactly as a shader reads them: through the runtime-lookup API
// of src/export/runtime/gtso_lookup.h, the same source text the generated header and shader
// includes ship (axis warps, half-texel remap, trilinear with clamp to edge, the 4D fold, BC4
// decode), on the BC4 blocks that export writes and on the float tables.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace gtbake {

class GtsoLookup {
 public:
  virtual ~GtsoLookup() = default;
  // S₃(A, β, r_p): cos β = b·ωr (the 3D table assumes b = n, θo = β).
  virtual float s3(float A, float cos_beta, float r_p) const = 0;
  // S₄(A, β, r_p, θo): cos θo = n·ωr; the table assumes b in the plane of n and ωr.
  virtual float s4(float A, float cos_beta, float r_p, float cos_theta_o) const = 0;
};

enum class TexelSource { kBc4, kFloat };

struct TablesLookupInfo {
  std::string bc4_source;    // where the BC4 blocks came from (a DDS file or the export encoder)
  double u_table_fit = 0.0;  // gtso.json cone.u: the u fitted against S₃ (shipped before)
  std::vector<float> s3_closed_form;  // gtso.json closed_form.coefficients, as shipped (float)
};

// Lookups for the tables in <luts>/gtso (gtso.json, gtso3d.f32, gtso4d.f32). BC4 texels come
// from <luts>/gtso3d.dds and gtso4d.dds, or, with encode_bc4 (or when the DDS files are absent),
// from encoding the float tables with the export's encoder (the blocks export writes).
struct TablesLookups {
  std::unique_ptr<GtsoLookup> bc4;
  std::unique_ptr<GtsoLookup> floats;
  TablesLookupInfo info;
};
TablesLookups makeTablesLookups(const std::filesystem::path& luts, bool encode_bc4, bool progress);

}  // namespace gtbake
