#include "screen_ao/screen_ao_command.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_lock.h"
#include "common/output_set.h"
#include "common/progress.h"
#include "common/text_escape.h"
#include "common/threads.h"
#include "gtbake_version.h"
#include "screen_ao/gbuffer.h"
#include "screen_ao/screen_ao_json.h"
#include "screen_ao/screen_ao_report.h"
#include "sweep/escape_image.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Runs one estimator on every image, timed, with a progress bar over images.
EstimatorRun runOne(const ScreenAoOptions& o, const std::string& name,
                    const std::vector<SweepImage>& images, std::vector<AoEstimate>* estimates) {
  EstimatorRun run;
  run.name = name;
  run.settings = settingsJson(o.settings, name);
  run.radius = estimatorRadius(o.settings, name);
  Progress bar("screen-ao " + name, images.size(), o.progress);
  const auto start = std::chrono::steady_clock::now();
  double pixels = 0.0;
  for (const SweepImage& image : images) {
    estimates->push_back(runEstimator(o.settings, name, image.gbuffer));
    pixels += static_cast<double>(image.gbuffer.pixels());
    bar.add(1);
  }
  bar.finish();
  run.seconds = secondsSince(start);
  run.megapixels = 1e-6 * pixels;
  const std::string channel = gbufferRadiusChannelName(run.radius);
  bool have = true;
  for (const SweepImage& image : images) have = have && image.truth.a_at_radius.count(channel) > 0;
  if (have) run.radius_channel = channel;
  run.errors = errorStatistics(images, *estimates, have ? run.radius : -1.0);
  return run;
}

void printRun(const EstimatorRun& run) {
  const ErrorSummary& e = run.errors.back().all;
  std::printf("%-16s %8.4f %8.4f %8s %8s %8.2f %8.2f %8.2f\n", run.name.c_str(), e.bias, e.rmse,
              e.pixels_at_radius ? std::to_string(e.bias_at_radius).substr(0, 7).c_str() : "-",
              e.pixels_at_radius ? std::to_string(e.rmse_at_radius).substr(0, 7).c_str() : "-",
              e.bent_mean_deg, e.bent_p95_deg,
              run.megapixels > 0 ? run.seconds / run.megapixels : 0.0);
  std::fflush(stdout);
}

}  // namespace

ScreenAoResult runScreenAo(const ScreenAoOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  if (o.sweep.empty()) throw Error("no sweep directory given: pass --sweep DIR");
  if (o.out.empty()) throw Error("no output directory given: pass --out DIR");
  if (o.estimators.empty()) throw Error("--estimators lists no estimator");
  validateSettings(o.settings);
  const OutputLock lock(o.out);  // for the whole run (output_lock.h)
  const ThreadLimit threads(o.threads);
  const SweepImages sweep = readSweepImages(o.sweep);
  OutputSet output(o.out, "screen_ao");

  nlohmann::ordered_json settings;
  settings["sweep"] = relativePath(o.sweep, o.out);
  settings["estimators"] = o.estimators;
  for (const std::string& name : o.estimators) settings[name] = settingsJson(o.settings, name);

  std::printf("%-16s %8s %8s %8s %8s %8s %8s %8s\n", "estimator", "bias", "RMSE", "bias@R",
              "RMSE@R", "bn mean", "bn p95", "s/MP");
  std::vector<EstimatorRun> runs;
  std::vector<std::vector<AoEstimate>> estimates(o.estimators.size());
  nlohmann::ordered_json estimators_json = nlohmann::ordered_json::object();
  ScreenAoResult result;
  for (std::size_t e = 0; e < o.estimators.size(); ++e) {
    runs.push_back(runOne(o, o.estimators[e], sweep.images, &estimates[e]));
    printRun(runs.back());
    estimators_json[o.estimators[e]] = estimatorJson(runs.back());
    if (o.estimators[e] == "gtao-reference") {
      const ErrorSummary& all = runs.back().errors.back().all;
      result.reference_rmse = all.pixels_at_radius ? all.rmse_at_radius : all.rmse;
    }
  }

  nlohmann::ordered_json json;
  json["gtbake_version"] = GTBAKE_VERSION;
  json["sweep_gtbake_version"] = sweep.sweep_version;
  json["settings"] = settings;
  json["images"] = nlohmann::ordered_json::array();
  for (const SweepImage& image : sweep.images) {
    json["images"].push_back({{"name", image.name},
                              {"scene", image.group},
                              {"file", fileSlug(image.name) + ".exr"},
                              {"width", image.gbuffer.width},
                              {"height", image.gbuffer.height}});
  }
  json["estimators"] = std::move(estimators_json);
  if (std::find(o.estimators.begin(), o.estimators.end(), "gtao-reference") != o.estimators.end()) {
    std::vector<const GBuffer*> gbuffers;
    for (const SweepImage& image : sweep.images) gbuffers.push_back(&image.gbuffer);
    const ReferenceConvergence c = referenceConvergence(gbuffers, o.settings.reference);
    std::printf(
        "gtao-reference convergence: doubling slices and steps moves A by %.5f RMS "
        "(max %.4f) over %zu pixels\n",
        c.rms_change, c.max_change, c.pixels);
    json["convergence"] = convergenceJson(c);
  }

  // The EXRs encoded in parallel (each into its own slot), added in order.
  std::vector<std::string> exrs(sweep.images.size());
  tbb::parallel_for(std::size_t(0), sweep.images.size(), [&](std::size_t k) {
    std::vector<AoEstimate> per_image;
    for (const auto& e : estimates) per_image.push_back(e[k]);
    exrs[k] = screenAoExr(sweep.images[k], o.estimators, per_image);
  });
  for (std::size_t k = 0; k < sweep.images.size(); ++k) {
    output.add(fileSlug(sweep.images[k].name) + ".exr", exrs[k]);
  }
  stageReport(&output, sweep.images, runs, estimates);
  result.seconds = secondsSince(start);
  json["seconds"] = result.seconds;
  output.setSettings(settings);
  output.add("screen_ao.json", json.dump(2) + "\n");
  output.commit();
  result.json = o.out / "screen_ao.json";
  return result;
}

}  // namespace gtbake
