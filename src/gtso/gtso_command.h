// `gtbake gtso`: the 3D and 4D GTSO tables and the cone-aperture constant u (SPEC §1.4).
#pragma once

#include <filesystem>

namespace gtbake {

struct GtsoOptions {
  std::filesystem::path out;  // gtso3d.f32, gtso4d.f32, gtso.json, slice images
  int size = 32;              // texels per axis
  int samples = 0;            // lobe samples per (r_p, θo, β) line; 0 = the documented default
  int threads = 0;            // 0 = all cores
  bool progress = true;
  // > 0: also bake both tables with reference_factor x the cells per axis (reference_factor^2 x
  // the lobe samples; 4 gives the SPEC's 16x) and record every texel's error against them in
  // gtso.json. Slow (about reference_factor^2 x the bake); bench_gtso measures the same.
  int reference_factor = 0;
};

struct GtsoResult {
  double u = 0.0;
  double u_se = 0.0;
  double seconds = 0.0;
};

GtsoResult runGtso(const GtsoOptions& options);

}  // namespace gtbake
