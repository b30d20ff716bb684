// Fuzz target: validate_data.json (parseValidateData, docs/fit.md §10), the file `validate --luts`
// reads, then the whole report on what it accepted (sums of hostile sizes must not reach undefined
// behaviour). The seed is the file of a real fit of a small synthetic sweep: four scenes of 300
// points whose G follows Eq. 10 with a scene-dependent offset. Anything but a gtbake::Error is a
// bug.
#include <cmath>
#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/input_limits.h"
#include "fit/fit_analysis.h"
#include "fit/validate_data.h"
#include "fit/validate_report.h"
#include "fuzz_target.h"

namespace gtbake::fuzz {

namespace {

// Four scenes (two types) with A spread over [0.02, 0.98] and G = Eq. 10 + an offset per scene;
// the halves differ by a deterministic ±0.002 so the fit has its noise estimate.
SweepData syntheticSweep() {
  SweepData d;
  d.spp = 8;
  d.bounces = 3;
  d.albedos = {0.2, 0.5, 0.8};
  d.full.G.resize(3);
  for (PointSet& h : d.half) h.G.resize(3);
  for (int s = 0; s < 4; ++s) {
    const std::size_t begin = d.full.A.size();
    for (int i = 0; i < 300; ++i) {
      const double A = 0.02 + 0.96 * std::fmod(0.618034 * (i + 300 * s), 1.0);
      const double wobble = 0.002 * std::sin(7.0 * i + s);
      d.full.A.push_back(A);
      d.half[0].A.push_back(A + wobble);
      d.half[1].A.push_back(A - wobble);
      for (std::size_t j = 0; j < 3; ++j) {
        const double G = evalMultiBounce(kPaperCoeffs, A, d.albedos[j]) + 0.01 * (s - 1.5) * A;
        d.full.G[j].push_back(G);
        d.half[0].G[j].push_back(G + wobble);
        d.half[1].G[j].push_back(G - wobble);
      }
    }
    d.scenes.push_back(
        {"s" + std::to_string(s), begin, d.full.A.size(), "", s < 2 ? "flat" : "rough"});
  }
  return d;
}

}  // namespace

std::vector<std::string> seeds() {
  const FitAnalysis a = analyzePoints(syntheticSweep(), {}, kPaperCoeffs, {20, 8, {0.95, 200, 1}});
  return {validateDataText(validateDataOf(a))};
}

}  // namespace gtbake::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gtbake;
  try {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const ValidateData d = parseValidateData(parseJsonText(text, "fuzz"), "fuzz");
    validateReport(d, kPaperCoeffs);
  } catch (const Error&) {
  }
  return 0;
}
