// `gtbake all`: scenes → sweep → fit → screen-ao → profiles → gtso → encode → validate-gtso →
// export with defaults (docs/index.md "Pipeline").
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace gtbake {

struct AllOptions {
  std::filesystem::path out = "luts";
  std::vector<std::filesystem::path>
      scenes;                // glTF files or directories; empty: the built-in corpus
  int threads = 0;           // 0 = all cores
  std::string command_line;  // recorded in the provenance of every generated file
  bool progress = true;
  std::string layout_4d = "atlas";  // --4d-layout: the 4D table's packing (encode_command.h)
};

// Layout of <out>: scenes/ (the built-in corpus, 12 types × 6 variants, generated only without
// `scenes`), <scene>.exr
// and sweep.json (the sweep), fit.json and report/ (the fit), screen_ao/ (the screen-space
// estimators), profiles/<estimator>/ (Equation 10 on each estimator's Â), gtso/ (float tables,
// gtso.json, slice images), and the exported gtbake_tables.{h,hlsl,glsl} and
// gtso{3d,4d}.{dds,ktx2}. Prints a summary of every figure.
void runAll(const AllOptions& options);

}  // namespace gtbake
