// `gtbake gtso`: the 3D and 4D GTSO tables, their end-to-end error per texel format, and the
// cone-aperture constant u (docs/gtso.md §1).
#pragma once

#include <cstdio>
#include <filesystem>
#include <vector>

namespace gtbake {

class OutputSet;

struct GtsoOptions {
  std::filesystem::path out;  // gtso3d.f32, gtso4d.f32, gtso.json, slice images
  int size = 32;              // texels per axis: a multiple of 4 in [4, 256]
  int lobe_cells = 0;         // phi cells of the lobe grid (psi gets 2x); 0 = the default 96
  int threads = 0;            // 0 = all cores
  bool progress = true;
  std::FILE* summary = stdout;  // where the closing summary lines go (nullptr: nowhere)
  // End-to-end error measurement: lobes per seed of the uniform set (16 points each; the stress
  // set has a quarter as many) and the number of seeds; the cone fit uses the first seed's
  // uniform 3D points.
  int error_lobes = 1024;
  int error_seeds = 3;
  // > 0: also bake both tables with reference_factor x the cells per axis (reference_factor^2 x
  // the lobe samples; 4 gives 16x) and record every texel's error against them in
  // gtso.json. Slow (about reference_factor^2 x the bake); bench_gtso measures the same.
  int reference_factor = 0;
  // The sampled texel check of every run (gtso/texel_check.h): this many random lines of the 3D
  // and 4D tables re-integrated at 4x the cells per side (16x reference); clamped to N^2.
  int texel_check_lines_3d = 64;
  int texel_check_lines_4d = 16;
  // Training lobes of the closed-form S3 fit (s3_closed_form.h; validation gets a quarter);
  // 0 = the shipped 2,048. Fewer fit faster and worse: tests of the stage's plumbing use 64.
  int closed_form_lobes = 0;
};

struct GtsoResult {
  double u = 0.0;
  double u_se = 0.0;
  double seconds = 0.0;
};

GtsoResult runGtso(const GtsoOptions& options);

// The slice previews of the tables (gtso3d_z*.png, gtso4d_z*_w*.png: S3 over (x, y) at a few z,
// S4 at a few (z, w)) staged in `output`; f3 and f4 in texture order, n texels per axis. `gtbake
// report` redraws them from the .f32 tables.
void writeGtsoPreviews(OutputSet& output, const std::vector<float>& f3,
                       const std::vector<float>& f4, int n);

}  // namespace gtbake
