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
#include "sweep/sweep_set.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Whether both bitmasks are requested with the same settings but their sector weights, so one
// pass serves both (docs/screen_ao.md §4).
bool bitmasksSharePass(const ScreenAoOptions& o) {
  const auto requested = [&](Estimator e) {
    return std::find(o.estimators.begin(), o.estimators.end(), e) != o.estimators.end();
  };
  const BitmaskSettings& u = o.settings.bitmask_uniform;
  const BitmaskSettings& c = o.settings.bitmask_cosine;
  return requested(Estimator::kBitmaskUniform) && requested(Estimator::kBitmaskCosine) &&
         sameBitmaskSamples(u, c) && u.thickness == c.thickness;
}

// The estimates of every image by the estimators `names` (one, or both bitmasks sharing a pass:
// [name][image]), with a progress bar over images; the pass's wall seconds are split evenly
// between them (docs/screen_ao.md §4).
std::vector<std::vector<AoEstimate>> runPass(const ScreenAoOptions& o,
                                             const std::vector<Estimator>& names,
                                             const std::vector<SweepImage>& images,
                                             double* seconds) {
  Progress bar("screen-ao " + estimatorListText(names, "+"), images.size(), o.progress);
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::vector<AoEstimate>> out(names.size());
  for (const SweepImage& image : images) {
    if (names.size() == 1) {
      out[0].push_back(runEstimator(o.settings, names[0], image.gbuffer));
    } else {
      std::vector<std::vector<AoEstimate>> both =
          visibilityBitmasks(image.gbuffer, o.settings.bitmask_uniform,
                             {SectorWeights::kUniform, SectorWeights::kCosine},
                             {o.settings.bitmask_uniform.thickness}, EstimateParts::kAoAndBent);
      for (std::size_t w = 0; w < names.size(); ++w) out[w].push_back(std::move(both[w][0]));
    }
    bar.add(1);
  }
  bar.finish();
  *seconds = secondsSince(start) / static_cast<double>(names.size());
  return out;
}

// One estimator's run from its estimates and seconds: settings, megapixels and errors (at
// `radius`, when the sweep holds A_R of it in every image; radius 0 = none).
EstimatorRun describeRun(const std::string& name, nlohmann::ordered_json settings, double radius,
                         const std::vector<SweepImage>& images,
                         const std::vector<AoEstimate>& estimates, double seconds) {
  EstimatorRun run;
  run.name = name;
  run.settings = std::move(settings);
  run.radius = radius;
  run.seconds = seconds;
  double pixels = 0.0;
  for (const SweepImage& image : images) pixels += static_cast<double>(image.gbuffer.pixels());
  run.megapixels = 1e-6 * pixels;
  const std::string channel = radius > 0.0 ? gbufferRadiusChannelName(run.radius) : "";
  bool have = radius > 0.0;
  for (const SweepImage& image : images) have = have && image.truth.a_at_radius.count(channel) > 0;
  if (have) run.radius_channel = channel;
  run.errors = errorStatistics(images, estimates, have ? run.radius : -1.0);
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

// Runs every estimator in order (both bitmasks in one pass when bitmasksSharePass), printing
// each one's line as soon as its estimates are in; estimates[e] is o.estimators[e]'s.
std::vector<EstimatorRun> runEstimators(const ScreenAoOptions& o,
                                        const std::vector<SweepImage>& images,
                                        std::vector<std::vector<AoEstimate>>* estimates) {
  const bool share = bitmasksSharePass(o);
  const auto index = [&](Estimator name) {
    return static_cast<std::size_t>(std::find(o.estimators.begin(), o.estimators.end(), name) -
                                    o.estimators.begin());
  };
  std::vector<double> seconds(o.estimators.size(), 0.0);
  std::vector<bool> done(o.estimators.size(), false);
  std::vector<EstimatorRun> runs;
  for (std::size_t e = 0; e < o.estimators.size(); ++e) {
    if (!done[e]) {
      const bool bitmask = describe(o.estimators[e]).bitmask != nullptr;
      const std::vector<Estimator> names =
          share && bitmask
              ? std::vector<Estimator>{Estimator::kBitmaskUniform, Estimator::kBitmaskCosine}
              : std::vector<Estimator>{o.estimators[e]};
      double pass_seconds = 0.0;
      auto out = runPass(o, names, images, &pass_seconds);
      for (std::size_t k = 0; k < names.size(); ++k) {
        const std::size_t at = index(names[k]);
        (*estimates)[at] = std::move(out[k]);
        seconds[at] = pass_seconds;
        done[at] = true;
      }
    }
    const Estimator name = o.estimators[e];
    runs.push_back(describeRun(describe(name).name, settingsJson(o.settings, name),
                               estimatorRadius(o.settings, name), images, (*estimates)[e],
                               seconds[e]));
    printRun(runs.back());
  }
  return runs;
}

nlohmann::ordered_json imagesJson(const std::vector<SweepImage>& images) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const SweepImage& image : images) {
    list.push_back({{"name", image.name},
                    {"scene", image.group},
                    {"file", fileSlug(image.name) + ".exr"},
                    {"width", image.gbuffer.width},
                    {"height", image.gbuffer.height}});
  }
  return list;
}

// An imported pass's settings in screen_ao.json: where it was read and its radius (null: none).
nlohmann::ordered_json importSettingsJson(const ImportedEstimator& e, const fs::path& out) {
  nlohmann::ordered_json j;
  j["import"] = relativePath(e.dir, out);
  j["radius"] = e.radius > 0.0 ? nlohmann::ordered_json(e.radius) : nlohmann::ordered_json(nullptr);
  return j;
}

// Every imported pass's estimates of every image ([import][image]), read and checked before
// anything runs (docs/screen_ao.md §8).
std::vector<std::vector<AoEstimate>> readImports(const ScreenAoOptions& o,
                                                 const std::vector<SweepImage>& images) {
  std::vector<std::vector<AoEstimate>> out;
  for (std::size_t k = 0; k < o.imports.size(); ++k) {
    const ImportedEstimator& e = o.imports[k];
    for (std::size_t l = 0; l < k; ++l) {
      if (o.imports[l].name == e.name) throw Error("--import: '" + e.name + "' is imported twice");
    }
    checkImportedName(e.name, "--import");
    checkImportRadius(e, images);
    out.emplace_back();
    for (const SweepImage& image : images) out.back().push_back(readImportedEstimate(e, image));
  }
  return out;
}

// The run's settings: the sweep, every estimator's name (built-in ones, then the imported ones)
// and each one's settings.
nlohmann::ordered_json runSettingsJson(const ScreenAoOptions& o) {
  nlohmann::ordered_json settings;
  settings["sweep"] = relativePath(o.sweep, o.out);
  settings["estimators"] = nlohmann::ordered_json::array();
  for (const Estimator e : o.estimators) settings["estimators"].push_back(describe(e).name);
  for (const Estimator e : o.estimators) settings[describe(e).name] = settingsJson(o.settings, e);
  for (const ImportedEstimator& e : o.imports) {
    settings["estimators"].push_back(e.name);
    settings[e.name] = importSettingsJson(e, o.out);
  }
  return settings;
}

// Appends the imported passes' estimates and runs (no time of their own: seconds 0).
void addImports(const ScreenAoOptions& o, const std::vector<SweepImage>& images,
                std::vector<std::vector<AoEstimate>>* imported, std::vector<EstimatorRun>* runs,
                std::vector<std::vector<AoEstimate>>* estimates) {
  for (std::size_t k = 0; k < o.imports.size(); ++k) {
    const ImportedEstimator& e = o.imports[k];
    estimates->push_back(std::move((*imported)[k]));
    runs->push_back(describeRun(e.name, importSettingsJson(e, o.out), e.radius, images,
                                estimates->back(), 0.0));
    printRun(runs->back());
  }
}

}  // namespace

ScreenAoResult runScreenAo(const ScreenAoOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  if (o.sweep.empty()) throw Error("no sweep directory given: pass --sweep DIR");
  if (o.out.empty()) throw Error("no output directory given: pass --out DIR");
  if (o.estimators.empty() && o.imports.empty()) {
    throw Error("--estimators lists no estimator and nothing is imported");
  }
  validateSettings(o.settings);
  const OutputLock lock(o.out);  // for the whole run (output_lock.h)
  const ThreadLimit threads(o.threads);
  const SweepImages sweep = readSweepImages(o.sweep);
  std::vector<std::vector<AoEstimate>> imported = readImports(o, sweep.images);
  OutputSet output(o.out, "screen_ao");

  const nlohmann::ordered_json settings = runSettingsJson(o);
  const std::vector<std::string> names = settings["estimators"].get<std::vector<std::string>>();

  std::printf("%-16s %8s %8s %8s %8s %8s %8s %8s\n", "estimator", "bias", "RMSE", "bias@R",
              "RMSE@R", "bn mean", "bn p95", "s/MP");
  std::vector<std::vector<AoEstimate>> estimates(o.estimators.size());
  std::vector<EstimatorRun> runs = runEstimators(o, sweep.images, &estimates);
  addImports(o, sweep.images, &imported, &runs, &estimates);
  nlohmann::ordered_json estimators_json = nlohmann::ordered_json::object();
  ScreenAoResult result;
  for (const EstimatorRun& run : runs) {
    estimators_json[run.name] = estimatorJson(run);
    if (findEstimator(run.name) == Estimator::kGtaoReference) {
      const ErrorSummary& all = run.errors.back().all;
      result.reference_rmse = all.pixels_at_radius ? all.rmse_at_radius : all.rmse;
    }
  }

  nlohmann::ordered_json json;
  json["gtbake_version"] = GTBAKE_VERSION;
  json["sweep_gtbake_version"] = sweep.sweep_version;
  json["settings"] = settings;
  json["images"] = imagesJson(sweep.images);
  json["estimators"] = std::move(estimators_json);
  if (std::find(o.estimators.begin(), o.estimators.end(), Estimator::kGtaoReference) !=
      o.estimators.end()) {
    std::vector<const GBuffer*> gbuffers;
    for (const SweepImage& image : sweep.images) gbuffers.push_back(&image.gbuffer);
    const ReferenceConvergence c = referenceConvergence(gbuffers, o.settings.reference);
    std::printf(
        "%s convergence: doubling slices and steps moves A by %.5f RMS (max %.4f) over %zu "
        "pixels\n",
        describe(Estimator::kGtaoReference).name, c.rms_change, c.max_change, c.pixels);
    json["convergence"] = convergenceJson(c);
  }

  // The EXRs encoded in parallel (each into its own slot), added in order.
  std::vector<std::string> exrs(sweep.images.size());
  tbb::parallel_for(std::size_t(0), sweep.images.size(), [&](std::size_t k) {
    std::vector<AoEstimate> per_image;
    for (const auto& e : estimates) per_image.push_back(e[k]);
    exrs[k] = screenAoExr(sweep.images[k], names, per_image);
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
