// `gtbake all`: scenes → sweep → fit → screen-ao → profiles → tune → lighting → gtso → encode →
// validate-gtso → export with defaults (docs/index.md "Pipeline").
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

// Writes the layout of docs/reproducibility.md "Layout" into <out>: scenes/ (the built-in corpus,
// 12 types × 6 variants, generated only without `scenes`), sweep/, fit/ (fit.json and report/),
// screen_ao/, profiles/<estimator>/ (Equation 10 on each estimator's Â), tune/, lighting/, gtso/,
// encode/, validate_gtso/, ship/ (the exported header, includes and volumes), timings.json (each
// stage's wall and CPU seconds, pipeline/stage_clock.h) and index.html; refuses a directory in
// the older flat layout. Prints a summary of every figure.
void runAll(const AllOptions& options);

}  // namespace gtbake
