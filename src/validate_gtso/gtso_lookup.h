// What the runtime reads from the shipped GTSO tables, behind one thin interface.
//
// validate-gtso scores S₃ and S₄ exactly as a shader reads them: through the runtime-lookup API
// of src/runtime/gtso_runtime.h, the same source text the generated header and shader
// includes ship (axis warps, half-texel remap, trilinear with clamp to edge, the 4D fold, BC4
// decode), on the BC4, R16_UNORM and R8_UNORM volumes that export writes and on the float tables.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "runtime/gtso_runtime.h"

namespace gtbake {

class GtsoLookup {
 public:
  virtual ~GtsoLookup() = default;
  // S₃(A, β, r_p): cos β = b·ωr (the 3D table assumes b = n, θo = β).
  virtual float s3(float A, float cos_beta, float r_p) const = 0;
  // S₄(A, β, r_p, θo): cos θo = n·ωr; the table assumes b in the plane of n and ωr.
  virtual float s4(float A, float cos_beta, float r_p, float cos_theta_o) const = 0;
  // The same lookups split where the runtime's split: the axis warps (gtso3DAxes, gtso4DAxes),
  // which depend only on the inputs and the table sizes, then the rest of gtso3DLookup and
  // gtso4DLookup on them. s3At(axes3(A, cos β, r_p)) is s3(A, cos β, r_p) to the bit, and so is
  // s3At of the axes of any lookup of the same sizes (every lookup of one TablesLookups).
  virtual GtsoAxisT<float> axes3(float A, float cos_beta, float r_p) const = 0;
  virtual GtsoAxisT<float> axes4(float A, float cos_beta, float r_p, float cos_theta_o) const = 0;
  virtual float s3At(const GtsoAxisT<float>& axes) const = 0;
  virtual float s4At(const GtsoAxisT<float>& axes) const = 0;
};

struct TablesLookupInfo {
  std::string bc4_source;            // the DDS files the BC4 blocks came from
  std::string r16_source;            // the DDS files of the R16_UNORM texels
  std::string r8_source;             // the same for R8_UNORM
  std::string layout_3d, layout_4d;  // texture layouts of the volumes read, as swizzles ("yzx")
  double u_table_fit = 0.0;          // gtso.json cone.u: the u fitted against S₃ (shipped before)
  std::vector<float> s3_closed_form;  // gtso.json closed_form.coefficients, as shipped (float)
};

// Lookups for the tables in <luts>/gtso (gtso.json, gtso3d.f32, gtso4d.f32) and the volumes
// `gtbake encode` wrote into <luts> (gtso{3d,4d}{,_r16,_r8}.dds in encode.json's layouts, read
// through encode/shipped_volumes.h, which verifies them against encode.manifest.json and the
// tables). All four read the sizes of the same two tables.
struct TablesLookups {
  std::unique_ptr<GtsoLookup> bc4;
  std::unique_ptr<GtsoLookup> r16;
  std::unique_ptr<GtsoLookup> r8;
  std::unique_ptr<GtsoLookup> floats;
  TablesLookupInfo info;
};
TablesLookups makeTablesLookups(const std::filesystem::path& luts);

}  // namespace gtbake
