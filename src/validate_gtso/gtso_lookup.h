// What the runtime reads from the shipped GTSO tables, behind one thin interface.
//
// validate-gtso scores S₃ and S₄ exactly as a shader reads them: through the runtime-lookup API
// of src/export/runtime/gtso_lookup.h, the same source text the generated header and shader
// includes ship (axis warps, half-texel remap, trilinear with clamp to edge, the 4D fold, BC4
// decode), on the BC4, R16_UNORM and R8_UNORM volumes that export writes and on the float tables.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace gtbake {

struct GtsoLayouts;  // export/bc4_layout.h

class GtsoLookup {
 public:
  virtual ~GtsoLookup() = default;
  // S₃(A, β, r_p): cos β = b·ωr (the 3D table assumes b = n, θo = β).
  virtual float s3(float A, float cos_beta, float r_p) const = 0;
  // S₄(A, β, r_p, θo): cos θo = n·ωr; the table assumes b in the plane of n and ωr.
  virtual float s4(float A, float cos_beta, float r_p, float cos_theta_o) const = 0;
};

struct TablesLookupInfo {
  std::string bc4_source;  // where the BC4 blocks came from (a DDS file or the export encoder)
  std::string r16_source;  // where the R16_UNORM texels came from (DDS files or quantised)
  std::string r8_source;   // the same for R8_UNORM
  std::string layout_3d, layout_4d;  // texture layouts of the volumes read, as swizzles ("yzx")
  double u_table_fit = 0.0;          // gtso.json cone.u: the u fitted against S₃ (shipped before)
  std::vector<float> s3_closed_form;  // gtso.json closed_form.coefficients, as shipped (float)
};

// Lookups for the tables in <luts>/gtso (gtso.json, gtso3d.f32, gtso4d.f32). BC4 texels come
// from <luts>/gtso3d.dds and gtso4d.dds, or, with encode_bc4 (or when the DDS files are absent),
// from encoding the float tables with the export's encoder (the blocks export writes). R16 and R8
// texels likewise come from <luts>/gtso{3d,4d}_r16.dds / _r8.dds, or from quantising the float
// tables with the export's quantizeUnorm (the texels export writes).
struct TablesLookups {
  std::unique_ptr<GtsoLookup> bc4;
  std::unique_ptr<GtsoLookup> r16;
  std::unique_ptr<GtsoLookup> r8;
  std::unique_ptr<GtsoLookup> floats;
  TablesLookupInfo info;
};
// The DDS files are read in the layouts of <luts>/export.json (identity when absent); encoded
// volumes use `layouts` (the choice export will ship; `gtbake all` passes it) or, when null,
// chooseLayouts' own choice (export/bc4_layout.h).
TablesLookups makeTablesLookups(const std::filesystem::path& luts, bool encode_bc4, bool progress,
                                const GtsoLayouts* layouts = nullptr);

}  // namespace gtbake
