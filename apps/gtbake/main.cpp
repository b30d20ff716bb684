// gtbake: the command-line shell. Parses into each stage's options struct, calls one library entry
// point per subcommand, and turns failures into one line on stderr and a non-zero exit.
//
// Each subcommand is one add<Name>Command function: it registers the subcommand and its options
// and returns the step that runs it once the command line has parsed. To add a subcommand, write
// its function and list it in registerSubcommands.
#include <glog/logging.h>
#include <malloc.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "common/error.h"
#include "common/text_escape.h"
#include "encode/encode_command.h"
#include "export/export_command.h"
#include "fit/fit_command.h"
#include "gtbake_version.h"
#include "gtso/gtso_command.h"
#include "lighting/lighting_command.h"
#include "option_values.h"
#include "pipeline/all_command.h"
#include "pipeline/report_command.h"
#include "scene/scenes_command.h"
#include "screen_ao/gbuffer_export.h"
#include "screen_ao/screen_ao_command.h"
#include "sweep/merge_command.h"
#include "sweep/specular_occlusion.h"
#include "sweep/sweep_command.h"
#include "tune/tune_command.h"
#include "validate_gtso/validate_gtso_command.h"

namespace {

// Buffers up to this size come from the heap, and freed heap space up to it is kept (main).
constexpr int kMallocKeepBytes = 1 << 30;

using namespace gtbake;

constexpr int kExitError = 1;  // bad input or a failed stage
constexpr int kExitUsage = 2;  // the command line itself did not parse
// validate's verdicts (docs/fit.md §10): consistent exits 0.
constexpr int kExitOutside = 3;      // the constants are outside the band (beyond --fail-above)
constexpr int kExitCannotJudge = 4;  // too few scenes to judge

int verdictExitCode(Verdict verdict) {
  switch (verdict) {
    case Verdict::kOutside:
      return kExitOutside;
    case Verdict::kTooFewScenes:
      return kExitCannotJudge;
    case Verdict::kConsistent:
      break;
  }
  return 0;
}

// What every subcommand's run step gets from the shell.
struct RunContext {
  bool progress = true;
  std::string command_line;  // "gtbake <arguments>", for provenance
};

struct Subcommand {
  CLI::App* parser = nullptr;
  // Called only if this subcommand was given; returns the exit code of a run without error.
  std::function<int(const RunContext&)> run;
};

std::string joinArguments(int argc, char** argv) {
  std::string line = "gtbake";
  for (int i = 1; i < argc; ++i) line += std::string(" ") + argv[i];
  return line;
}

// CLI11 prefixes messages with the option's own name; keep the first line only.
std::string firstLine(const std::string& text) {
  return text.substr(0, text.find('\n'));
}

// --estimator and --screen-ao of fit, validate and validate-gtso (parseAoInput): a profile's A
// (and, for validate-gtso, its bent normal).
struct AoInputText {
  std::string estimator;
  std::string screen_ao;
  std::string truth = "near";
};
std::shared_ptr<AoInputText> addAoInputOptions(
    CLI::App* parser, const char* what =
                          "Fit on this screen-space estimator's A instead of the "
                          "ray-traced A (a profile; docs/profiles.md)") {
  auto text = std::make_shared<AoInputText>();
  parser->add_option("--estimator", text->estimator, what);
  parser->add_option("--screen-ao", text->screen_ao,
                     "Directory from gtbake screen-ao (default: <sweep>/screen_ao)");
  parser
      ->add_option("--truth", text->truth,
                   "With --estimator: score against the near-field truth at the estimator's "
                   "radius (near) or the unbounded one (unbounded); docs/sweep.md")
      ->capture_default_str();
  return text;
}

// --threads, the same for every stage; ThreadLimit (common/threads.h) checks the value.
void addThreadsOption(CLI::App* parser, int& threads) {
  parser->add_option("--threads", threads, "Worker threads (0 = all cores)");
}

Subcommand addScenesCommand(CLI::App& app) {
  auto options = std::make_shared<ScenesOptions>();
  auto seed = std::make_shared<std::string>(std::to_string(options->seed));
  auto* parser = app.add_subcommand("scenes", "Write the procedural scene corpus as glTF");
  parser->add_option("--out", options->out, "Output directory")->required();
  parser->add_option("--seed", *seed, "Seed of the variants (and the classic clutter, terrain)");
  parser->add_option("--variants", options->variants, "Variants per scene type")
      ->capture_default_str();
  parser->add_flag("--classic", options->classic, "Only the seven classic scenes (data/scenes)");
  return {parser, [options, seed](const RunContext& context) {
            options->seed = parseSeed(*seed, "--seed");
            options->progress = context.progress;
            runScenes(*options);
            return 0;
          }};
}

Subcommand addSweepCommand(CLI::App& app) {
  auto options = std::make_shared<SweepOptions>();
  auto resolution = std::make_shared<std::string>(std::to_string(options->width) + "x" +
                                                  std::to_string(options->height));
  auto* parser = app.add_subcommand("sweep", "Path-trace A and G(rho) per pixel with Embree");
  parser->add_option("--scenes", options->scenes, "glTF files or directories of them")->required();
  parser->add_option("--out", options->out, "Output directory")->required();
  parser->add_option("--spp", options->spp, "Random walks per pixel (even)")->capture_default_str();
  parser->add_option("--res", *resolution, "Resolution WxH")->capture_default_str();
  parser->add_option("--bounces", options->bounces, "Interreflections K counted in G")
      ->capture_default_str();
  parser->add_option("--radius", options->radius, "Sky beyond this distance (default unbounded)");
  auto seed = std::make_shared<std::string>(std::to_string(options->seed));
  parser->add_option("--seed", *seed, "Random seed")->capture_default_str();
  parser->add_option("--camera", options->camera,
                     "Camera of a glTF with several: its name or index (default: the first); "
                     "auto[:K]: K views framing each scene (the default without a camera)");
  addThreadsOption(parser, options->threads);
  auto specular_roughness =
      std::make_shared<std::string>(specularRoughnessList(options->specular_roughness));
  parser
      ->add_option("--specular-roughness", *specular_roughness,
                   "Perceptual roughness values of the S channels, or none")
      ->capture_default_str();
  parser->add_option("--specular-spp", options->specular_spp, "VNDF samples per roughness (even)")
      ->capture_default_str();
  auto gbuffer_radii = std::make_shared<std::string>(gbufferRadiusList(options->gbuffer_radii));
  parser
      ->add_option("--gbuffer-radius", *gbuffer_radii,
                   "Radii (m) of the A_R channels (A with the sky beyond R), or none")
      ->capture_default_str();
  auto transfer = std::make_shared<std::string>("on");
  parser
      ->add_option("--transfer", *transfer,
                   "Per-bounce SH transfer channels T<k>_SH<i> (docs/sweep.md, \"Transfer\")")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  auto shard = std::make_shared<std::string>();
  parser->add_option("--shard", *shard,
                     "Trace only shard I of N (0 <= I < N) into --out, for gtbake merge");
  parser->add_flag("--resume", options->resume,
                   "Continue an interrupted sweep from the tiles saved in --out");
  return {parser, [options, resolution, seed, specular_roughness, gbuffer_radii, transfer,
                   shard](const RunContext& context) {
            std::tie(options->width, options->height) = parseResolution(*resolution);
            options->transfer = *transfer == "on";
            options->seed = parseSeed(*seed, "--seed");
            options->specular_roughness = parseSpecularRoughness(*specular_roughness);
            options->gbuffer_radii = parseGbufferRadii(*gbuffer_radii);
            if (!shard->empty()) std::tie(options->shard, options->shards) = parseShard(*shard);
            options->command_line = context.command_line;
            options->progress = context.progress;
            runSweep(*options);
            return 0;
          }};
}

Subcommand addMergeCommand(CLI::App& app) {
  auto options = std::make_shared<MergeOptions>();
  auto* parser = app.add_subcommand("merge", "Combine the shard directories of a sharded sweep");
  parser->add_option("--out", options->out, "Output directory (as gtbake sweep --out)")->required();
  parser->add_option("shards", options->shards, "Shard directories (gtbake sweep --shard)")
      ->required();
  return {parser, [options](const RunContext&) {
            runMerge(*options);
            return 0;
          }};
}

Subcommand addFitCommand(CLI::App& app) {
  auto options = std::make_shared<FitOptions>();
  auto shipped = std::make_shared<std::string>();
  auto* parser = app.add_subcommand("fit", "Fit Equation 10 to a sweep with Ceres");
  parser->add_option("--sweep", options->sweep, "Directory written by gtbake sweep")->required();
  parser->add_option("--out", options->out, "fit.json to write")->required();
  parser->add_option("--report", options->report, "HTML report directory (default: beside --out)");
  auto* shipped_option =
      parser->add_option("--shipped", *shipped,
                         "Constants to compare against, a1,a0,b1,b0,c1,c0 (default: the paper's)");
  auto weighting = std::make_shared<std::string>("pixel");
  parser->add_option("--weighting", *weighting, "Point weights: pixel, view or flat-a")
      ->capture_default_str();
  parser->add_flag("--constrain-open", options->constrain_open,
                   "Constrain a - b + c = 1 (G(1, rho) = 1 for an open surface)");
  auto input = addAoInputOptions(parser);
  return {parser, [options, shipped, shipped_option, weighting, input](const RunContext& context) {
            if (shipped_option->count() > 0) options->shipped = parseCoeffs(*shipped, "--shipped");
            options->weighting = parseWeighting(*weighting);
            options->input =
                parseAoInput(input->estimator, input->screen_ao, input->truth, options->sweep);
            options->progress = context.progress;
            runFit(*options);
            return 0;
          }};
}

Subcommand addValidateCommand(CLI::App& app) {
  auto options = std::make_shared<ValidateOptions>();
  auto coeffs = std::make_shared<std::string>();
  auto* parser = app.add_subcommand(
      "validate",
      "Score Equation 10 constants by range of A against a sweep or a fit's shipped sums; exit "
      "0 consistent, 3 outside, 4 too few scenes to judge");
  parser->add_option("--sweep", options->sweep, "Directory written by gtbake sweep");
  parser->add_option("--luts", options->luts,
                     "A fit's output directory with validate_data.json (e.g. luts/fit): no images");
  auto* coeffs_option = parser->add_option("--coeffs", *coeffs,
                                           "a1,a0,b1,b0,c1,c0 (default: the paper's Equation 10)");
  auto weighting = std::make_shared<std::string>("pixel");
  parser->add_option("--weighting", *weighting, "Point weights of the refit")
      ->capture_default_str();
  auto input = addAoInputOptions(parser);
  auto json = std::make_shared<std::string>();
  auto* json_option = parser->add_option("--json", *json, "Also write the report as JSON");
  auto fail_above = std::make_shared<double>(0.0);
  auto* fail_option = parser->add_option(
      "--fail-above", *fail_above,
      "Tolerance in G: fail only where a range is outside by more than this (also the power a "
      "range needs to be judged; default 0.05)");
  return {parser, [=](const RunContext& context) {
            if (coeffs_option->count() > 0) options->coeffs = parseCoeffs(*coeffs);
            options->weighting = parseWeighting(*weighting);
            options->input =
                parseAoInput(input->estimator, input->screen_ao, input->truth, options->sweep);
            if (json_option->count() > 0) options->json = *json;
            if (fail_option->count() > 0) options->rule.fail_above = *fail_above;
            options->progress = context.progress;
            return verdictExitCode(runValidate(*options));
          }};
}

Subcommand addGtsoCommand(CLI::App& app) {
  auto options = std::make_shared<GtsoOptions>();
  auto* parser = app.add_subcommand("gtso", "Bake the 3D and 4D GTSO tables and fit u");
  parser->add_option("--out", options->out, "Output directory")->required();
  parser->add_option("--size", options->size, "Texels per axis")->capture_default_str();
  parser->add_option("--lobe-cells", options->lobe_cells,
                     "Lobe-grid phi cells N (psi gets 2N; 0 = default 96)");
  parser
      ->add_option("--error-lobes", options->error_lobes,
                   "Random lobes per seed of the end-to-end error (16 points each)")
      ->capture_default_str();
  parser->add_option("--error-seeds", options->error_seeds, "Seeds of the end-to-end error")
      ->capture_default_str();
  parser->add_option("--closed-form-lobes", options->closed_form_lobes,
                     "Training lobes of the closed-form S3 fit (0 = default 2048)");
  addThreadsOption(parser, options->threads);
  parser->add_option("--reference-factor", options->reference_factor,
                     "Also bake a reference with this many times the cells per axis and record "
                     "every texel's error in gtso.json (4 = 16x the samples; slow)");
  return {parser, [options](const RunContext& context) {
            options->progress = context.progress;
            runGtso(*options);
            return 0;
          }};
}

Subcommand addValidateGtsoCommand(CLI::App& app) {
  auto options = std::make_shared<ValidateGtsoOptions>();
  auto* parser = app.add_subcommand(
      "validate-gtso", "Score GTSO tables, cone model and baselines against path-traced S; fit u");
  parser->add_option("--sweep", options->sweep, "Sweep with specular channels")->required();
  parser->add_option("--luts", options->luts, "Directory laid out as gtbake all's: gtso/, encode/")
      ->required();
  parser->add_option("--u", options->u, "Also score the cone model with this u");
  parser->add_option("--out", options->out,
                     "Output directory (default: <luts>/validate_gtso; with --estimator "
                     "<luts>/profiles/<estimator>)");
  auto input = addAoInputOptions(
      parser,
      "Score on this screen-space estimator's A and bent normal instead of the ray-traced ones "
      "(docs/validate_gtso.md section 6; reads <luts>/validate_gtso/validate_gtso.json for the "
      "fitted u)");
  parser->add_flag("--no-images", "Leave the per-view PNGs out of the report");
  return {parser, [options, input, parser](const RunContext& context) {
            options->input =
                parseAoInput(input->estimator, input->screen_ao, input->truth, options->sweep);
            options->write_images = parser->count("--no-images") == 0;
            options->progress = context.progress;
            runValidateGtso(*options);
            return 0;
          }};
}

Subcommand addEncodeCommand(CLI::App& app) {
  auto options = std::make_shared<EncodeOptions>();
  auto* parser =
      app.add_subcommand("encode", "BC4/R16/R8 volumes (DDS, KTX2) in the chosen texture layouts");
  parser->add_option("--gtso", options->gtso, "Directory from gtbake gtso")->required();
  parser->add_option("--out", options->out, "Output directory")->required();
  addThreadsOption(parser, options->threads);
  auto layout4D = std::make_shared<std::string>("atlas");
  parser->add_option("--4d-layout", *layout4D,
                     "4D table: atlas (theta_o slices tiled, every extent <= 256) or fold "
                     "(32x32x1024 for 32^4; D3D, Metal, OpenGL 4 only)");
  return {parser, [options, layout4D](const RunContext& context) {
            options->progress = context.progress;
            options->layout_4d = parseLayout4D(*layout4D);
            runEncode(*options);
            return 0;
          }};
}

Subcommand addExportCommand(CLI::App& app) {
  auto options = std::make_shared<ExportOptions>();
  auto* parser = app.add_subcommand("export", "The C++ header and HLSL/GLSL includes");
  parser->add_option("--fit", options->fit, "fit.json from gtbake fit")->required();
  parser->add_option("--gtso", options->gtso, "Directory from gtbake gtso")->required();
  parser->add_option("--out", options->out, "Output directory")->required();
  parser->add_option("--encode", options->encode,
                     "Directory from gtbake encode (default: --out); elsewhere, its volumes are "
                     "copied into --out");
  parser->add_option("--validate-gtso", options->validate_gtso,
                     "validate_gtso.json whose u (fitted to path-traced S) the header ships");
  parser->add_option("--profiles", options->profiles,
                     "Directory of engine profiles, <estimator>/fit.json from gtbake fit "
                     "--estimator (docs/profiles.md)");
  parser->add_option("--tune", options->tune,
                     "tune.json from gtbake tune: ship the tuned settings with the profile "
                     "refitted at each (docs/tune.md)");
  return {parser, [options](const RunContext& context) {
            options->command_line = context.command_line;
            runExport(*options);
            return 0;
          }};
}

Subcommand addScreenAoCommand(CLI::App& app) {
  auto options = std::make_shared<ScreenAoOptions>();
  auto estimators = std::make_shared<std::string>("all");
  auto settings = std::make_shared<std::vector<std::string>>();
  auto imports = std::make_shared<std::vector<std::string>>();
  auto* parser = app.add_subcommand(
      "screen-ao", "Screen-space A and bent normals from a sweep's G-buffer vs ray-traced truth");
  parser->add_option("--sweep", options->sweep, "Directory written by gtbake sweep")->required();
  parser->add_option("--out", options->out, "Output directory")->required();
  parser
      ->add_option("--estimators", *estimators,
                   estimatorListText(screenAoEstimators(), ",") + ", all or none")
      ->capture_default_str();
  parser->add_option("--setting", *settings,
                     "ESTIMATOR.KEY=VALUE, repeatable (e.g. gtao-runtime.directions=8, "
                     "all.radius=0.5; docs/screen_ao.md)");
  parser->add_option("--import", *imports,
                     "NAME=DIR[:radius=R], repeatable: your own pass's <image>.exr files (channel "
                     "A, optional BNX BNY BNZ) computed on `gtbake gbuffer`'s output, scored as "
                     "estimator NAME (docs/screen_ao.md §8)");
  addThreadsOption(parser, options->threads);
  return {parser, [options, estimators, settings, imports](const RunContext& context) {
            options->estimators = parseEstimatorList(*estimators);
            for (const std::string& s : *settings) applySetting(&options->settings, s);
            for (const std::string& s : *imports) options->imports.push_back(parseImport(s));
            options->progress = context.progress;
            runScreenAo(*options);
            return 0;
          }};
}

Subcommand addGbufferCommand(CLI::App& app) {
  auto options = std::make_shared<GbufferExportOptions>();
  auto* parser = app.add_subcommand(
      "gbuffer",
      "Write a sweep's G-buffer (depth, normals, cameras) for your own screen-space pass");
  parser->add_option("--sweep", options->sweep, "Directory written by gtbake sweep")->required();
  parser->add_option("--out", options->out, "Output directory")->required();
  addThreadsOption(parser, options->threads);
  return {parser, [options](const RunContext&) {
            runGbufferExport(*options);
            return 0;
          }};
}

Subcommand addTuneCommand(CLI::App& app) {
  auto options = std::make_shared<TuneOptions>();
  auto estimators = std::make_shared<std::string>(estimatorListText(tunedEstimators(), ","));
  auto* parser = app.add_subcommand(
      "tune",
      "Find the screen-space AO settings whose A, fed to Equation 10, best matches path-traced "
      "multi-bounce G (docs/tune.md)");
  parser->footer(
      "For each setting (one at a time, every other at the estimator's default) every grid value "
      "is run on the sweep's G-buffer and scored by the RMSE of G over every pixel and albedo: "
      "once with the paper's constants, once with Equation 10 refitted on that A (the profile). "
      "Each optimum comes with a 95 % interval over scene mixes (delete-one-scene jackknife) and "
      "the range within 5 % of the best RMSE. Searched: gtao-runtime radius (m), intensity, "
      "thin_compensation; bitmask-uniform/-cosine thickness (m). Writes <out>/tune.json and "
      "<out>/report/tune.html.");
  parser->add_option("--sweep", options->sweep, "Directory written by gtbake sweep")->required();
  parser->add_option("--out", options->out, "Output directory")->required();
  parser
      ->add_option("--estimators", *estimators,
                   "Comma-separated: " + estimatorListText(tunedEstimators(), ", "))
      ->capture_default_str();
  parser->add_option("--grid", options->grids,
                     "ESTIMATOR.KEY=v1,v2,... replaces a default grid, repeatable; must hold the "
                     "default (e.g. gtao-runtime.radius=0.5,1,2,3)");
  parser->add_option("--screen-ao", options->screen_ao,
                     "A gtbake screen-ao set of the same sweep: the estimators it ran at their "
                     "defaults are read from it, not run again (docs/tune.md §7)");
  auto truth = std::make_shared<std::string>("near");
  parser
      ->add_option("--truth", *truth,
                   "near: score against the near-field truth at the estimators' default radius "
                   "(1 m); unbounded: against the unbounded G (docs/tune.md §1)")
      ->check(CLI::IsMember({"near", "unbounded"}))
      ->capture_default_str();
  addThreadsOption(parser, options->threads);
  return {parser, [options, estimators, truth](const RunContext& context) {
            options->estimators = parseEstimatorList(*estimators);
            options->unbounded_truth = *truth == "unbounded";
            options->progress = context.progress;
            runTune(*options);
            return 0;
          }};
}

Subcommand addLightingCommand(CLI::App& app) {
  auto options = std::make_shared<LightingOptions>();
  auto* parser = app.add_subcommand(
      "lighting", "Equation 10 under environments, from a sweep's transfer channels");
  parser->add_option("--sweep", options->sweep, "Directory written by gtbake sweep (--transfer on)")
      ->required();
  parser
      ->add_option("--env", options->environments,
                   "Equirectangular EXR files or classes: uniform, overcast, horizon, sun-sky, "
                   "window (docs/lighting.md §2)")
      ->required();
  parser->add_option("--fit", options->fit, "fit.json of gtbake fit, scored beside the paper's");
  parser->add_option("--out", options->out, "Output directory")->required();
  return {parser, [options](const RunContext& context) {
            options->progress = context.progress;
            runLighting(*options);
            return 0;
          }};
}

Subcommand addAllCommand(CLI::App& app) {
  auto options = std::make_shared<AllOptions>();
  auto* parser = app.add_subcommand("all",
                                    "scenes, sweep, fit, screen-ao, profiles, tune, gtso, encode, "
                                    "validate-gtso and export with defaults");
  parser->add_option("--out", options->out, "Output directory, one folder per stage")
      ->capture_default_str();
  addThreadsOption(parser, options->threads);
  parser->add_option("--scenes", options->scenes,
                     "glTF files or directories of them (default: the built-in corpus)");
  parser->add_option("--4d-layout", options->layout_4d,
                     "4D table: atlas (default, every extent <= 256) or fold (encode)");
  return {parser, [options](const RunContext& context) {
            // The output directory and thread count do not change a byte of the results, so the
            // provenance records the canonical command and luts/ reproduces from any --out.
            options->command_line = "gtbake all";
            for (const auto& scene : options->scenes) {
              options->command_line += " --scenes " + scene.string();
            }
            if (parseLayout4D(options->layout_4d) == Layout4D::kFold) {
              options->command_line += " --4d-layout fold";
            }
            options->progress = context.progress;
            runAll(*options);
            return 0;
          }};
}

Subcommand addReportCommand(CLI::App& app) {
  auto options = std::make_shared<ReportOptions>();
  auto* parser = app.add_subcommand(
      "report",
      "Draw the pictures and pages of a gtbake all directory again from its data, each checked "
      "against its manifest (docs/reproducibility.md)");
  parser->add_option("--luts", options->luts, "Output directory of gtbake all")->required();
  parser->add_option("--out", options->out, "Where the pictures and pages go (may be --luts)")
      ->required();
  addThreadsOption(parser, options->threads);
  return {parser, [options](const RunContext& context) {
            options->progress = context.progress;
            runReport(*options);
            return 0;
          }};
}

// The subcommands in the order --help lists them.
std::vector<Subcommand> registerSubcommands(CLI::App& app) {
  std::vector<Subcommand> subcommands;
  subcommands.push_back(addScenesCommand(app));
  subcommands.push_back(addSweepCommand(app));
  subcommands.push_back(addMergeCommand(app));
  subcommands.push_back(addFitCommand(app));
  subcommands.push_back(addValidateCommand(app));
  subcommands.push_back(addGtsoCommand(app));
  subcommands.push_back(addValidateGtsoCommand(app));
  subcommands.push_back(addEncodeCommand(app));
  subcommands.push_back(addExportCommand(app));
  subcommands.push_back(addScreenAoCommand(app));
  subcommands.push_back(addGbufferCommand(app));
  subcommands.push_back(addTuneCommand(app));
  subcommands.push_back(addLightingCommand(app));
  subcommands.push_back(addAllCommand(app));
  subcommands.push_back(addReportCommand(app));
  return subcommands;
}

// Parses the command line. Returns the exit code if the shell should stop here (help, version,
// or a parse error printed as one line), or nothing if a subcommand is to run.
std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv) {
  // An unknown word where the subcommand goes is named as such (CLI11 would say "A subcommand is
  // required").
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') continue;
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands({})) known = known || sub->get_name() == word;
    if (!known) {
      std::fprintf(stderr, "gtbake: error: unknown subcommand '%s' (see gtbake --help)\n",
                   word.c_str());
      return kExitUsage;
    }
    break;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "gtbake: error: %s (see gtbake --help)\n", firstLine(e.what()).c_str());
    return kExitUsage;
  }
  return std::nullopt;
}

// Runs the subcommand that was given; gtbake::Error is bad input, anything else a bug.
int runSelectedSubcommand(const std::vector<Subcommand>& subcommands, const RunContext& context) {
  try {
    for (const Subcommand& subcommand : subcommands) {
      if (*subcommand.parser) return subcommand.run(context);
    }
  } catch (const gtbake::SweepInterrupted& e) {
    std::fprintf(stderr, "gtbake: %s\n", firstLine(e.what()).c_str());
    return 128 + e.signal();
  } catch (const gtbake::Error& e) {
    std::fprintf(stderr, "gtbake: error: %s\n", firstLine(e.what()).c_str());
    return kExitError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gtbake: internal error: %s\n", firstLine(e.what()).c_str());
    return kExitError;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Stage after stage allocates and frees buffers of megabytes (file bytes, decoded images,
  // tables). By default glibc maps each one above its mmap threshold afresh, so the kernel faults
  // in and zeroes its pages again, and it hands freed heap tops back to the kernel. Up to 1 GiB,
  // a buffer comes from the heap and a freed one is kept for the next (docs/performance.md
  // "Allocation"); the bytes gtbake computes are the same either way.
  mallopt(M_MMAP_THRESHOLD, kMallocKeepBytes);
  mallopt(M_TRIM_THRESHOLD, kMallocKeepBytes);
  CLI::App app{"gtbake " GTBAKE_VERSION
               ": regenerate GTAO/GTSO constants and "
               "tables from path-traced ground truth"};
  app.require_subcommand(1);
  app.fallthrough();  // --quiet is accepted after the subcommand too
  app.set_version_flag("--version", GTBAKE_VERSION);
  bool quiet = false;
  app.add_flag("--quiet,-q", quiet, "No progress bars (results still go to stdout)");
  const std::vector<Subcommand> subcommands = registerSubcommands(app);
  // Ceres logs through glog: keep its warnings off stderr so a failure stays one error line.
  google::InitGoogleLogging(argv[0]);
  FLAGS_minloglevel = google::GLOG_FATAL;
  FLAGS_logtostderr = true;
  // Paths and names end up in JSON, which must be UTF-8 (docs/limits.md §Paths).
  for (int i = 1; i < argc; ++i) {
    if (!isValidUtf8(argv[i])) {
      std::fprintf(stderr,
                   "gtbake: error: argument %d is not valid UTF-8 (gtbake records paths in JSON; "
                   "rename the file)\n",
                   i);
      return kExitError;
    }
  }
  if (const std::optional<int> exit_code = parseCommandLine(app, argc, argv)) return *exit_code;
  return runSelectedSubcommand(subcommands, {!quiet, joinArguments(argc, argv)});
}
