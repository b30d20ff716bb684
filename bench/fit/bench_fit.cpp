// bench_fit: CPU time (all threads, std::clock) of each stage of `gtbake fit` on a sweep directory
// (default: the shipped luts/), median of RUNS runs. CPU time, not wall time, because the machine
// is shared: wall time measures the neighbours.
//
//   bench_fit [SWEEP_DIR] [RUNS]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "common/output_set.h"
#include "fit/fit_analysis.h"
#include "fit/fit_outputs.h"
#include "fit/fit_report.h"

namespace {

double cpuSeconds() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  using namespace gtbake;
  const std::filesystem::path sweep = argc > 1 ? argv[1] : "luts";
  const int runs = argc > 2 ? std::stoi(argv[2]) : 5;
  const char* names[] = {"loadSweep",    "fitMultiBounce", "sceneJackknife",
                         "errors+score", "weightings",     "constraint",
                         "floor",        "report",         "fit.json"};
  constexpr int kStages = 9;
  std::vector<std::vector<double>> times(kStages);
  std::vector<double> total;
  for (int r = 0; r < runs; ++r) {
    const double start = cpuSeconds();
    double last = start;
    int stage = 0;
    const auto mark = [&] {
      const double now = cpuSeconds();
      times[stage++].push_back(now - last);
      last = now;
    };
    FitAnalysis a;
    a.data = loadSweep(sweep);
    mark();
    a.fit = fitMultiBounce(a.data, {});
    mark();
    a.jackknife = sceneJackknife(a.data, a.fit, kPaperCoeffs);
    mark();
    a.refit_errors = errorTable(a.data, a.fit.linear.coeffs);
    a.shipped_errors = errorTable(a.data, kPaperCoeffs);
    a.shipped_difference = maxCurveDifference(a.fit.linear.coeffs, kPaperCoeffs);
    a.shipped_score = scoreAgainstBand(a.jackknife, a.fit.linear.coeffs, kPaperCoeffs);
    a.view_weights = viewWeights(a.data, a.fit.weights);
    mark();
    a.weightings = weightingAlternatives(a.data, a.fit);
    mark();
    a.constraint = constraintAlternative(a.data, a.fit);
    mark();
    a.floor = fitFloor(a.data);
    mark();
    {
      OutputSet report("/tmp/bench_fit_report", "fit_report");
      writeFitReport(report, "", a, kPaperCoeffs);
      report.commit();
    }
    mark();
    const ValidateReport shipped = validateReport(validateDataOf(a), kPaperCoeffs);
    const std::string json = fitJson("/tmp/bench_fit.json", a, kPaperCoeffs, shipped).dump(2);
    mark();
    total.push_back(cpuSeconds() - start);
  }
  std::printf("bench_fit: %s, median CPU seconds of %d runs (single process)\n",
              sweep.string().c_str(), runs);
  for (int s = 0; s < kStages; ++s) std::printf("  %-16s %8.4f\n", names[s], median(times[s]));
  std::printf("  %-16s %8.4f\n", "total", median(total));
  return 0;
}
