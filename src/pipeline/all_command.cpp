#include "pipeline/all_command.h"

#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdio>

#include "common/atomic_file.h"
#include "common/output_layout.h"
#include "common/output_lock.h"
#include "common/progress.h"
#include "common/threads.h"
#include "encode/encode_command.h"
#include "export/export_command.h"
#include "fit/fit_command.h"
#include "gtso/gtso_command.h"
#include "lighting/lighting_command.h"
#include "pipeline/index_page.h"
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

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void banner(const char* stage, bool enabled) {
  if (enabled) std::fprintf(stderr, "\n== gtbake all: %s ==\n", stage);
}

// The seconds of the stages whose results carry no time of their own.
struct StageTimes {
  double scenes, fit, profiles, tune, lighting, specular_profiles, exporter, total;
};

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
// ray-traced run, whose u it scores); each run is threaded inside, so they run one after another.
double specularProfiles(const AllOptions& options, std::vector<Profile>* profiles) {
  banner("validate-gtso per estimator", options.progress);
  const auto t = std::chrono::steady_clock::now();
  // Once for every estimator of the same radius (all of them with the defaults): S_R at it, and
  // the unbounded S scored beside it.
  std::optional<SpecularSweep> sweep;
  std::optional<SpecularSweep> unbounded;
  for (Profile& p : *profiles) {
    ValidateGtsoOptions v;
    v.sweep = options.out / kSweepDir;
    v.luts = options.out;
    v.input.estimator = p.estimator;
    v.input.screen_ao = options.out / kScreenAoDir;
    const std::optional<double> radius = truthRadius(v.input);
    if (!sweep || sweep->radius != radius) sweep = readSpecularSweep(v.sweep, radius);
    v.sweep_data = &*sweep;
    if (radius && !unbounded) unbounded = readSpecularSweep(v.sweep);
    v.unbounded_sweep_data = unbounded ? &*unbounded : nullptr;
    v.write_images = false;  // 72 PNGs per estimator; `gtbake validate-gtso --estimator` draws them
    v.print_summary = false;
    v.progress = options.progress;
    p.specular = runValidateGtso(v);
  }
  return secondsSince(t);
}

// Screen-space A and bent normals from the sweep's G-buffer into <out>/screen_ao, then one
// profile per estimator into <out>/profiles/<estimator>/ (fit.json and its report).
ScreenAoResult screenAndProfiles(const AllOptions& options, int threads,
                                 std::vector<Profile>* profiles, double* profile_seconds) {
  banner("screen-ao", options.progress);
  ScreenAoOptions screen_ao;
  screen_ao.sweep = options.out / kSweepDir;
  screen_ao.out = options.out / kScreenAoDir;
  screen_ao.threads = threads;
  screen_ao.progress = options.progress;
  const ScreenAoResult screened = runScreenAo(screen_ao);

  banner("profiles", options.progress);
  const auto t = std::chrono::steady_clock::now();
  // The fits are independent (each its own output set) and mostly serial inside, so they run side
  // by side; the summary table below prints their results in the estimators' order.
  const std::vector<Estimator>& estimators = screen_ao.estimators;
  profiles->assign(estimators.size(), {});
  Progress bar("profiles", estimators.size(), options.progress);
  tbb::parallel_for(std::size_t{0}, estimators.size(), [&](std::size_t k) {
    FitOptions fit;
    fit.sweep = screen_ao.sweep;
    fit.out = options.out / kProfilesDir / describe(estimators[k]).name / "fit.json";
    fit.input.estimator = describe(estimators[k]).name;
    fit.input.screen_ao = screen_ao.out;
    fit.write_report = false;  // 72 scatter plots per profile; `gtbake fit --estimator` draws them
    // validate --estimator reads the sweep (the shipped sums are the ray-traced fit's only).
    fit.write_validate_data = false;
    fit.progress = false;
    fit.print_summary = false;
    (*profiles)[k] = {describe(estimators[k]).name, runFit(fit), {}};
    bar.add(1);
  });
  bar.finish();
  *profile_seconds = secondsSince(t);
  return screened;
}

void printSummary(const AllOptions& options, const SweepResult& swept, const FitResult& fitted,
                  const GtsoResult& baked, const EncodeResult& encoded,
                  const ValidateGtsoResult& validated, const ScreenAoResult& screened,
                  const std::vector<Profile>& profiles, const StageTimes& times) {
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
  std::printf(
      "  time             scenes %.1f s, sweep %.1f s (%.1f Mrays/s), fit %.1f s, screen-ao %.1f s,"
      " profiles %.1f s, tune %.1f s, lighting %.1f s, gtso %.1f s, encode %.1f s, validate-gtso"
      " %.1f s (per estimator %.1f s), export %.1f s; total %.1f s\n",
      times.scenes, swept.seconds, swept.seconds > 0 ? swept.rays / swept.seconds * 1e-6 : 0.0,
      times.fit, screened.seconds, times.profiles, times.tune, times.lighting, baked.seconds,
      encoded.seconds, validated.seconds, times.specular_profiles, times.exporter, times.total);
}

// The scenes (the user's, or the built-in corpus written into <out>/scenes at its settings) and
// their sweep into <out>; *scenes_seconds is the time spent writing the corpus.
SweepResult sweepScenes(const AllOptions& options, int threads, double* scenes_seconds) {
  const auto t = std::chrono::steady_clock::now();
  std::vector<std::filesystem::path> gltf = options.scenes;
  const bool corpus = gltf.empty();
  if (corpus) {
    banner("scenes", options.progress);
    ScenesOptions scenes;
    scenes.out = options.out / "scenes";
    scenes.progress = options.progress;
    gltf = runScenes(scenes);
  }
  *scenes_seconds = secondsSince(t);

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
// Returns its seconds.
double lightingStage(const AllOptions& options, const std::filesystem::path& fit) {
  banner("lighting", options.progress);
  const auto t = std::chrono::steady_clock::now();
  LightingOptions lighting;
  lighting.sweep = options.out / kSweepDir;
  lighting.environments = environmentClasses();
  lighting.fit = fit;
  lighting.out = options.out / kLightingDir;
  lighting.print_summary = false;  // lighting/lighting.json and its report hold it
  runLighting(lighting);
  return secondsSince(t);
}

}  // namespace

void runAll(const AllOptions& options) {
  const OutputLock lock(options.out);  // every stage writes inside it (output_lock.h)
  refuseFlatLayout(options.out, "gtbake all");
  ensureDirectory(options.out);
  const ThreadLimit limit(options.threads);
  const auto start = std::chrono::steady_clock::now();

  double scenes_seconds = 0.0;
  const SweepResult swept = sweepScenes(options, limit.threads(), &scenes_seconds);
  const std::filesystem::path swept_dir = options.out / kSweepDir;

  banner("fit", options.progress);
  FitOptions fit;
  fit.sweep = swept_dir;
  fit.out = options.out / kFitDir / "fit.json";
  fit.report = options.out / kFitDir / "report";
  fit.progress = options.progress;
  auto t = std::chrono::steady_clock::now();
  const FitResult fitted = runFit(fit);
  const double fit_seconds = secondsSince(t);

  std::vector<Profile> profiles;
  double profile_seconds = 0.0;
  const ScreenAoResult screened =
      screenAndProfiles(options, limit.threads(), &profiles, &profile_seconds);

  const TuneResult tuned = tuneSettings(options, limit.threads());
  const double lighting_seconds = lightingStage(options, fit.out);

  banner("gtso", options.progress);
  GtsoOptions gtso;
  gtso.out = options.out / kGtsoDir;
  gtso.threads = limit.threads();
  gtso.progress = options.progress;
  const GtsoResult baked = runGtso(gtso);

  banner("encode", options.progress);
  EncodeOptions encode;
  encode.gtso = gtso.out;
  encode.out = options.out / kEncodeDir;  // gtso{3d,4d}*.dds/.ktx2, encode.json
  encode.threads = limit.threads();
  encode.progress = options.progress;
  encode.layout_4d = parseLayout4D(options.layout_4d);
  const EncodeResult encoded = runEncode(encode);

  banner("validate-gtso", options.progress);
  ValidateGtsoOptions validate_gtso;
  validate_gtso.sweep = swept_dir;
  validate_gtso.luts = options.out;  // <out>/gtso, <out>/encode; writes <out>/validate_gtso
  validate_gtso.progress = options.progress;
  const ValidateGtsoResult validated = runValidateGtso(validate_gtso);
  const double specular_profile_seconds = specularProfiles(options, &profiles);

  banner("export", options.progress);
  ExportOptions exporter;
  exporter.fit = fit.out;
  exporter.gtso = gtso.out;
  exporter.encode = encode.out;
  exporter.validate_gtso = validated.json;
  exporter.profiles = options.out / kProfilesDir;
  exporter.tune = tuned.json;             // empty when tune was skipped
  exporter.out = options.out / kShipDir;  // the header, the includes, the volumes, README.md
  exporter.command_line = options.command_line;
  t = std::chrono::steady_clock::now();
  runExport(exporter);
  const double export_seconds = secondsSince(t);
  writeIndexPage(options.out);

  StageTimes times{scenes_seconds, fit_seconds,        profile_seconds,
                   tuned.seconds,  lighting_seconds,   specular_profile_seconds,
                   export_seconds, secondsSince(start)};
  printSummary(options, swept, fitted, baked, encoded, validated, screened, profiles, times);
}

}  // namespace gtbake
