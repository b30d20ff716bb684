#include "pipeline/all_command.h"

#include <tbb/parallel_for.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_layout.h"
#include "common/output_lock.h"
#include "common/progress.h"
#include "common/threads.h"
#include "encode/encode_command.h"
#include "export/export_command.h"
#include "fit/fit_command.h"
#include "gtso/gtso_command.h"
#include "lighting/lighting_command.h"
#include "pipeline/background_chain.h"
#include "pipeline/index_page.h"
#include "pipeline/stage_clock.h"
#include "scene/scenes_command.h"
#include "screen_ao/screen_ao_command.h"
#include "sweep/sweep_command.h"
#include "tune/tune_command.h"
#include "validate_gtso/specular_sweep.h"
#include "validate_gtso/validate_gtso_command.h"

namespace gtbake {

namespace {

// The default corpus keeps the ray budget of the seven classic scenes at the sweep's defaults
// (7 × 192² pixels × 384 walks and 64 specular samples per roughness): 72 views × 128² pixels
// are 4.57 times the pixels, so 84 walks and 14 specular samples per pixel, the same totals
// (docs/scenes.md).
constexpr int kCorpusResolution = 128;
constexpr int kCorpusSpp = 84;
constexpr int kCorpusSpecularSpp = 14;

void banner(const char* stage, bool enabled) {
  if (enabled) std::fprintf(stderr, "\n== gtbake all: %s ==\n", stage);
}

// One estimator's profile: Equation 10 refitted on its Â (docs/profiles.md), and specular
// occlusion scored on its Â and b̂ (docs/validate_gtso.md §6).
struct Profile {
  std::string estimator;
  FitResult fit;
  ValidateGtsoResult specular;
};

// The overall RMSE of S of `method` in a validate-gtso result (0 when it was not scored).
double specularRmse(const ValidateGtsoResult& r, const char* method) {
  for (const auto& [name, rmse] : r.rmse) {
    if (name == method) return rmse;
  }
  return 0.0;
}

// validate-gtso on every profile's estimator, into <out>/profiles/<estimator>/ (after the
// ray-traced run, whose u it scores). The truth each reads (S at its estimator's radius, and the
// unbounded S scored beside it) is read once per radius first; then the runs, each its own output
// set and threaded inside, run side by side, since their serial parts would leave a core idle.
void specularProfiles(const AllOptions& options, std::vector<Profile>* profiles) {
  banner("validate-gtso per estimator", options.progress);
  const std::filesystem::path sweep_dir = options.out / kSweepDir;
  std::vector<ValidateGtsoOptions> runs(profiles->size());
  std::map<std::optional<double>, SpecularSweep> truth;  // by radius; none: the unbounded S
  for (std::size_t k = 0; k < runs.size(); ++k) {
    ValidateGtsoOptions& v = runs[k];
    v.sweep = sweep_dir;
    v.luts = options.out;
    v.input.estimator = (*profiles)[k].estimator;
    v.input.screen_ao = options.out / kScreenAoDir;
    const std::optional<double> radius = truthRadius(v.input);
    for (const std::optional<double>& r : {radius, std::optional<double>()}) {
      if (truth.count(r) == 0) truth.emplace(r, readSpecularSweep(sweep_dir, r));
      if (!radius) break;
    }
    v.sweep_data = &truth.at(radius);
    v.unbounded_sweep_data = radius ? &truth.at(std::nullopt) : nullptr;
    v.write_images = false;  // 72 PNGs per estimator; `gtbake validate-gtso --estimator` draws them
    v.print_summary = false;
    v.progress = false;
  }
  Progress bar("validate-gtso per estimator", runs.size(), options.progress);
  tbb::parallel_for(std::size_t{0}, runs.size(), [&](std::size_t k) {
    (*profiles)[k].specular = runValidateGtso(runs[k]);
    bar.add(1);
  });
  bar.finish();
}

// Screen-space A and bent normals from the sweep's G-buffer into <out>/screen_ao.
ScreenAoResult screenAo(const AllOptions& options, int threads) {
  banner("screen-ao", options.progress);
  ScreenAoOptions screen_ao;
  screen_ao.sweep = options.out / kSweepDir;
  screen_ao.out = options.out / kScreenAoDir;
  screen_ao.threads = threads;
  screen_ao.progress = options.progress;
  return runScreenAo(screen_ao);
}

// One profile per estimator of screen-ao's defaults into <out>/profiles/<estimator>/ (fit.json).
std::vector<Profile> profilesOf(const AllOptions& options) {
  banner("profiles", options.progress);
  // The fits are independent (each its own output set) and mostly serial inside, so they run side
  // by side; the summary table below prints their results in the estimators' order.
  // The truth each fit reads (G at its estimator's radius, and the unbounded G it is also scored
  // against) is read once per radius first and copied into each fit.
  const std::vector<Estimator>& estimators = ScreenAoOptions{}.estimators;
  std::vector<FitOptions> fits(estimators.size());
  LoadedSweeps truth;
  for (std::size_t k = 0; k < fits.size(); ++k) {
    FitOptions& fit = fits[k];
    fit.sweep = options.out / kSweepDir;
    fit.out = options.out / kProfilesDir / describe(estimators[k]).name / "fit.json";
    fit.input.estimator = describe(estimators[k]).name;
    fit.input.screen_ao = options.out / kScreenAoDir;
    for (const std::optional<double>& r : {truthRadius(fit.input), std::optional<double>()}) {
      if (truth.count(r) == 0) truth.emplace(r, loadSweep(fit.sweep, r));
    }
    fit.loaded_sweeps = &truth;
    fit.write_report = false;  // 72 scatter plots per profile; `gtbake fit --estimator` draws them
    // validate --estimator reads the sweep (the shipped sums are the ray-traced fit's only).
    fit.write_validate_data = false;
    fit.progress = false;
    fit.print_summary = false;
  }
  std::vector<Profile> profiles(estimators.size());
  Progress bar("profiles", estimators.size(), options.progress);
  tbb::parallel_for(std::size_t{0}, estimators.size(), [&](std::size_t k) {
    profiles[k] = {describe(estimators[k]).name, runFit(fits[k]), {}};
    bar.add(1);
  });
  bar.finish();
  return profiles;
}

void printSummary(const AllOptions& options, const SweepResult& swept, const FitResult& fitted,
                  const GtsoResult& baked, const EncodeResult& encoded,
                  const ValidateGtsoResult& validated, const ScreenAoResult& screened,
                  const std::vector<Profile>& profiles, const StageClock& clock) {
  std::printf("\ngtbake all: summary (%s)\n", options.out.c_str());
  std::printf("  Equation 10      refit ± SE scenes (SE Monte Carlo)   paper     refit - paper\n");
  for (size_t i = 0; i < 6; ++i) {
    std::printf("  %-4s %16.4f ± %.4f (%.5f) %12.4f %+12.4f\n", kCoeffNames[i], fitted.linear[i],
                fitted.scene_se[i], fitted.linear_se[i], kPaperCoeffs[i],
                fitted.linear[i] - kPaperCoeffs[i]);
  }
  std::printf("  curve band       max SE of G %.4f; paper: %s\n", fitted.band_max,
              fitted.verdict.c_str());
  std::printf(
      "  cone aperture u  %.3g, 5%% interval [%.3g, %.3g] vs path-traced S (paper: 0.01;"
      " table fit %.3g; docs/validate_gtso.md)\n",
      validated.u, validated.u_low, validated.u_high, baked.u);
  std::printf("  BC4 3D table     RMSE %.2e  max %.2e\n", encoded.bc4_rmse_3d, encoded.bc4_max_3d);
  std::printf("  BC4 4D table     RMSE %.2e  max %.2e\n", encoded.bc4_rmse_4d, encoded.bc4_max_4d);
  std::printf(
      "  screen-space AO  gtao-reference RMSE %.4f vs ray-traced A at its radius"
      " (screen_ao/screen_ao.json)\n",
      screened.reference_rmse);
  std::printf(
      "  profiles         RMSE of G on the estimator's A: paper | refit held out by scene\n");
  for (const Profile& p : profiles) {
    std::printf("    %-16s %.4f | %.4f  (profiles/%s/fit.json)\n", p.estimator.c_str(),
                p.fit.shipped_rmse, p.fit.held_out_rmse, p.estimator.c_str());
  }
  std::printf(
      "  specular on it   RMSE of S on the estimator's A and b: S4_bc4 | cone_ao2_u_0.01 |"
      " lagarde\n");
  for (const Profile& p : profiles) {
    std::printf("    %-16s %.4f | %.4f | %.4f  (profiles/%s/validate_gtso.json)\n",
                p.estimator.c_str(), specularRmse(p.specular, "S4_bc4"),
                specularRmse(p.specular, "cone_ao2_u_0.01"), specularRmse(p.specular, "lagarde"),
                p.estimator.c_str());
  }
  std::printf("  time             %s (timings.json; %.1f Mrays/s in the sweep)\n",
              stageTimeLine(clock).c_str(),
              swept.seconds > 0 ? swept.rays / swept.seconds * 1e-6 : 0.0);
}

// The built-in corpus, written into <out>/scenes.
std::vector<std::filesystem::path> corpusScenes(const AllOptions& options) {
  banner("scenes", options.progress);
  ScenesOptions scenes;
  scenes.out = options.out / "scenes";
  scenes.progress = options.progress;
  return runScenes(scenes);
}

// The sweep of `gltf` into <out>/sweep, at the corpus settings when `corpus`.
SweepResult sweepScenes(const AllOptions& options, int threads,
                        const std::vector<std::filesystem::path>& gltf, bool corpus) {
  banner("sweep", options.progress);
  SweepOptions sweep;
  sweep.scenes = gltf;
  sweep.out = options.out / kSweepDir;  // <out>/sweep/<view>.exr, as the README promises
  sweep.threads = threads;
  sweep.progress = options.progress;
  if (corpus) {
    sweep.width = sweep.height = kCorpusResolution;
    sweep.spp = kCorpusSpp;
    sweep.specular_spp = kCorpusSpecularSpp;
  }
  return runSweep(sweep);
}

// The estimators' settings against the near-field truth (docs/tune.md) into <out>/tune, reading
// screen-ao's default runs; an empty result when the sweep has too few scenes for its intervals.
TuneResult tuneSettings(const AllOptions& options, int threads) {
  banner("tune", options.progress);
  TuneOptions tune;
  tune.sweep = options.out / kSweepDir;
  tune.out = options.out / kTuneDir;
  tune.screen_ao = options.out / kScreenAoDir;  // its defaults' Â, not run again (docs/tune.md §7)
  tune.threads = threads;
  tune.progress = options.progress;
  try {
    return runTune(tune);
  } catch (const TuneNotApplicable& e) {  // nothing written
    std::fprintf(stderr, "gtbake all: tune skipped: %s\n", e.what());
    return {};
  }
}

// Equation 10 under the built-in environment classes against the sweep's transfer channels
// (docs/lighting.md) into <out>/lighting.
void lightingStage(const AllOptions& options, const std::filesystem::path& fit) {
  banner("lighting", options.progress);
  LightingOptions lighting;
  lighting.sweep = options.out / kSweepDir;
  lighting.environments = environmentClasses();
  lighting.fit = fit;
  lighting.out = options.out / kLightingDir;
  lighting.print_summary = false;  // lighting/lighting.json and its report hold it
  lighting.progress = options.progress;
  runLighting(lighting);
}

// The ray-traced fit into <out>/fit (fit.json and its report).
FitResult fitStage(const AllOptions& options) {
  banner("fit", options.progress);
  FitOptions fit;
  fit.sweep = options.out / kSweepDir;
  fit.out = options.out / kFitDir / "fit.json";
  fit.report = options.out / kFitDir / "report";
  fit.progress = options.progress;
  return runFit(fit);
}

// The GTSO tables into <out>/gtso and their BC4 volumes into <out>/encode, their summary lines
// to `summary`; progress and banners only when that is stdout (the stages in the foreground).
GtsoResult gtsoStage(const AllOptions& options, int threads, std::FILE* summary) {
  const bool progress = options.progress && summary == stdout;
  banner("gtso", progress);
  GtsoOptions gtso;
  gtso.out = options.out / kGtsoDir;
  gtso.threads = threads;
  gtso.progress = progress;
  gtso.summary = summary;
  return runGtso(gtso);
}

EncodeResult encodeStage(const AllOptions& options, int threads, std::FILE* summary) {
  const bool progress = options.progress && summary == stdout;
  banner("encode", progress);
  EncodeOptions encode;
  encode.gtso = options.out / kGtsoDir;
  encode.out = options.out / kEncodeDir;  // gtso{3d,4d}*.dds/.ktx2, encode.json
  encode.threads = threads;
  encode.progress = progress;
  encode.summary = summary;
  encode.layout_4d = parseLayout4D(options.layout_4d);
  return runEncode(encode);
}

// gtso and encode read nothing another stage writes, and no stage before validate-gtso reads
// what they write, so with more than one thread they run as a chain beside the stages from
// scenes to lighting, on the cores those leave idle (docs/performance.md "Stages in the
// background"). Their summary lines wait in memory until the foreground reaches them.
class TablesInBackground {
 public:
  TablesInBackground(const AllOptions& options, int threads, StageClock* clock)
      : clock_(clock), progress_(options.progress), summary_(open_memstream(&text_, &size_)) {
    if (summary_ == nullptr) throw Error("gtbake all: no memory for the background summary");
    chain_.emplace(threads, [this, &options, threads](BackgroundChain& chain) {
      chain.run("gtso", [&] { baked_ = gtsoStage(options, threads, summary_); });
      chain.run("encode", [&] { encoded_ = encodeStage(options, threads, summary_); });
    });
    clock_->setBackgroundCpu([this] { return chain_->cpuSeconds(); });
  }
  ~TablesInBackground() {
    chain_.reset();  // cancels and waits before the stream it writes to closes
    std::fclose(summary_);
    std::free(text_);
  }
  TablesInBackground(const TablesInBackground&) = delete;
  TablesInBackground& operator=(const TablesInBackground&) = delete;

  // Waits for the chain, adds its stages to the clock and prints their summary lines.
  void join(GtsoResult* baked, EncodeResult* encoded) {
    banner("gtso and encode (ran in the background)", progress_);
    const BackgroundChain::Joined joined = chain_->join();
    clock_->setBackgroundCpu(nullptr);
    clock_->addBackground(joined.stages, joined.waited_seconds);
    std::fflush(summary_);
    std::fwrite(text_, 1, size_, stdout);
    *baked = baked_;
    *encoded = encoded_;
  }

 private:
  StageClock* clock_;
  bool progress_;
  char* text_ = nullptr;
  std::size_t size_ = 0;
  std::FILE* summary_;
  GtsoResult baked_;
  EncodeResult encoded_;
  std::optional<BackgroundChain> chain_;
};

ValidateGtsoResult validateGtsoStage(const AllOptions& options) {
  banner("validate-gtso", options.progress);
  ValidateGtsoOptions validate_gtso;
  validate_gtso.sweep = options.out / kSweepDir;
  validate_gtso.luts = options.out;  // <out>/gtso, <out>/encode; writes <out>/validate_gtso
  validate_gtso.progress = options.progress;
  return runValidateGtso(validate_gtso);
}

void exportStage(const AllOptions& options, const TuneResult& tuned,
                 const ValidateGtsoResult& validated) {
  banner("export", options.progress);
  ExportOptions exporter;
  exporter.fit = options.out / kFitDir / "fit.json";
  exporter.gtso = options.out / kGtsoDir;
  exporter.encode = options.out / kEncodeDir;
  exporter.validate_gtso = validated.json;
  exporter.profiles = options.out / kProfilesDir;
  exporter.tune = tuned.json;             // empty when tune was skipped
  exporter.out = options.out / kShipDir;  // the header, the includes, the volumes, README.md
  exporter.command_line = options.command_line;
  runExport(exporter);
}

}  // namespace

void runAll(const AllOptions& options) {
  const OutputLock lock(options.out);  // every stage writes inside it (output_lock.h)
  refuseFlatLayout(options.out, "gtbake all");
  ensureDirectory(options.out);
  const ThreadLimit limit(options.threads);
  const int threads = limit.threads();
  StageClock clock;
  std::optional<TablesInBackground> tables;
  if (threads > 1) tables.emplace(options, threads, &clock);

  std::vector<std::filesystem::path> gltf = options.scenes;
  if (gltf.empty()) clock.run("scenes", [&] { gltf = corpusScenes(options); });
  SweepResult swept;
  clock.run("sweep", [&] { swept = sweepScenes(options, threads, gltf, options.scenes.empty()); });
  FitResult fitted;
  clock.run("fit", [&] { fitted = fitStage(options); });
  ScreenAoResult screened;
  clock.run("screen-ao", [&] { screened = screenAo(options, threads); });
  std::vector<Profile> profiles;
  clock.run("profiles", [&] { profiles = profilesOf(options); });
  TuneResult tuned;
  clock.run("tune", [&] { tuned = tuneSettings(options, threads); });
  clock.run("lighting", [&] { lightingStage(options, options.out / kFitDir / "fit.json"); });
  GtsoResult baked;
  EncodeResult encoded;
  if (tables) {
    tables->join(&baked, &encoded);
  } else {
    clock.run("gtso", [&] { baked = gtsoStage(options, threads, stdout); });
    clock.run("encode", [&] { encoded = encodeStage(options, threads, stdout); });
  }
  ValidateGtsoResult validated;
  clock.run("validate-gtso", [&] { validated = validateGtsoStage(options); });
  clock.run("validate-gtso per estimator", [&] { specularProfiles(options, &profiles); });
  clock.run("export", [&] { exportStage(options, tuned, validated); });
  writeTimings(options.out, clock, threads);
  writeIndexPage(options.out);
  printSummary(options, swept, fitted, baked, encoded, validated, screened, profiles, clock);
}

}  // namespace gtbake
