#include "tune/tune_command.h"

#include <chrono>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_lock.h"
#include "common/output_set.h"
#include "common/threads.h"
#include "tune/tune_analysis.h"
#include "tune/tune_outputs.h"

namespace gtbake {

std::vector<SettingGrid> tuneGrids(const TuneOptions& o) {
  if (o.estimators.empty()) throw Error("--estimators lists no estimator");
  std::vector<SettingGrid> grids = defaultGrids(o.estimators);
  for (const std::string& text : o.grids) applyGridOption(&grids, text);
  return grids;
}

TuneResult runTune(const TuneOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  if (o.sweep.empty()) throw Error("no sweep directory given: pass --sweep DIR");
  if (o.out.empty()) throw Error("no output directory given: pass --out DIR");
  const std::vector<SettingGrid> grids = tuneGrids(o);
  const OutputLock lock(o.out);  // for the whole run (output_lock.h)
  const ThreadLimit threads(o.threads);
  const std::optional<double> truth =
      o.unbounded_truth ? std::nullopt : std::optional<double>(o.truth_radius);
  const TuneAnalysis analysis =
      analyzeTune(o.sweep, grids, o.progress, o.screen_ao, truth, o.compute_ahead);
  OutputSet output(o.out, "tune");
  TuneResult result;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const TuneProvenance provenance{relativePath(o.sweep, o.out), result.seconds};
  output.setSettings(tuneSettingsJson(grids, provenance.sweep));
  output.add("tune.json", tuneJson(analysis, grids, provenance).dump(2) + "\n");
  output.add("report/tune.html", tuneReportHtml(analysis));
  output.commit();
  printTuneSummary(analysis);
  result.json = o.out / "tune.json";
  return result;
}

}  // namespace gtbake
