// gtbake: the command-line shell. Parses into each stage's options struct, calls one library entry
// point per subcommand, and turns failures into one line on stderr and a non-zero exit.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>
#include <tuple>

#include "common/error.h"
#include "export/export_command.h"
#include "fit/fit_command.h"
#include "gtbake_version.h"
#include "gtso/gtso_command.h"
#include "pipeline/all_command.h"
#include "pipeline/option_values.h"
#include "scene/scenes_command.h"
#include "sweep/specular_occlusion.h"
#include "sweep/sweep_command.h"
#include "validate_gtso/validate_gtso_command.h"

namespace {

constexpr int kExitError = 1;  // bad input or a failed stage
constexpr int kExitUsage = 2;  // the command line itself did not parse

std::string joinArguments(int argc, char** argv) {
  std::string line = "gtbake";
  for (int i = 1; i < argc; ++i) line += std::string(" ") + argv[i];
  return line;
}

// CLI11 prefixes messages with the option's own name; keep the first line only.
std::string firstLine(const std::string& text) {
  return text.substr(0, text.find('\n'));
}

}  // namespace

int main(int argc, char** argv) {
  using namespace gtbake;
  CLI::App app{"gtbake " GTBAKE_VERSION
               ": regenerate GTAO/GTSO constants and tables from path-traced ground truth"};
  app.require_subcommand(1);
  app.fallthrough();  // --quiet is accepted after the subcommand too
  app.set_version_flag("--version", GTBAKE_VERSION);
  bool quiet = false;
  app.add_flag("--quiet,-q", quiet, "No progress bars (results still go to stdout)");

  ScenesOptions scenes;
  auto* scenes_cmd = app.add_subcommand("scenes", "Write the seven procedural scene types as glTF");
  scenes_cmd->add_option("--out", scenes.out, "Output directory")->required();
  scenes_cmd->add_option("--seed", scenes.seed, "Seed of the clutter and terrain generators");

  SweepOptions sweep;
  std::string resolution = std::to_string(sweep.width) + "x" + std::to_string(sweep.height);
  auto* sweep_cmd = app.add_subcommand("sweep", "Path-trace A and G(rho) per pixel with Embree");
  sweep_cmd->add_option("--scenes", sweep.scenes, "glTF files or directories of them")->required();
  sweep_cmd->add_option("--out", sweep.out, "Output directory")->required();
  sweep_cmd->add_option("--spp", sweep.spp, "Random walks per pixel (even)")->capture_default_str();
  sweep_cmd->add_option("--res", resolution, "Resolution WxH")->capture_default_str();
  sweep_cmd->add_option("--bounces", sweep.bounces, "Interreflections K counted in G")
      ->capture_default_str();
  sweep_cmd->add_option("--radius", sweep.radius, "Sky beyond this distance (default unbounded)");
  sweep_cmd->add_option("--seed", sweep.seed, "Random seed")->capture_default_str();
  sweep_cmd->add_option("--threads", sweep.threads, "Worker threads (0 = all cores)");
  std::string specular_roughness = specularRoughnessList(sweep.specular_roughness);
  sweep_cmd
      ->add_option("--specular-roughness", specular_roughness,
                   "Perceptual roughness values of the S channels, or none")
      ->capture_default_str();
  sweep_cmd->add_option("--specular-spp", sweep.specular_spp, "VNDF samples per roughness (even)")
      ->capture_default_str();

  FitOptions fit;
  std::string fit_shipped;
  auto* fit_cmd = app.add_subcommand("fit", "Fit Equation 10 to a sweep with Ceres");
  fit_cmd->add_option("--sweep", fit.sweep, "Directory written by gtbake sweep")->required();
  fit_cmd->add_option("--out", fit.out, "fit.json to write")->required();
  fit_cmd->add_option("--report", fit.report, "HTML report directory (default: beside --out)");
  fit_cmd->add_option("--shipped", fit_shipped,
                      "Constants to compare against, a1,a0,b1,b0,c1,c0 (default: the paper's)");

  ValidateOptions validate;
  std::string validate_coeffs;
  auto* validate_cmd =
      app.add_subcommand("validate", "Score shipped Equation 10 constants against a sweep");
  validate_cmd->add_option("--sweep", validate.sweep, "Directory written by gtbake sweep")
      ->required();
  validate_cmd->add_option("--coeffs", validate_coeffs,
                           "a1,a0,b1,b0,c1,c0 (default: the paper's Equation 10)");

  GtsoOptions gtso;
  auto* gtso_cmd = app.add_subcommand("gtso", "Bake the 3D and 4D GTSO tables and fit u");
  gtso_cmd->add_option("--out", gtso.out, "Output directory")->required();
  gtso_cmd->add_option("--size", gtso.size, "Texels per axis")->capture_default_str();
  gtso_cmd->add_option("--samples", gtso.samples, "Lobe samples per line (0 = default)");
  gtso_cmd->add_option("--threads", gtso.threads, "Worker threads (0 = all cores)");
  gtso_cmd->add_option("--reference-factor", gtso.reference_factor,
                       "Also bake a reference with this many times the cells per axis and record "
                       "every texel's error in gtso.json (4 = 16x the samples; slow)");

  ValidateGtsoOptions validate_gtso;
  auto* validate_gtso_cmd = app.add_subcommand(
      "validate-gtso", "Score GTSO tables, cone model and baselines against path-traced S; fit u");
  validate_gtso_cmd->add_option("--sweep", validate_gtso.sweep, "Sweep with specular channels")
      ->required();
  validate_gtso_cmd->add_option("--luts", validate_gtso.luts, "Directory with gtso/ and gtso*.dds")
      ->required();
  validate_gtso_cmd->add_option("--u", validate_gtso.u, "Also score the cone model with this u");
  validate_gtso_cmd->add_option("--out", validate_gtso.out, "Output directory (default: --luts)");

  ExportOptions exporter;
  auto* export_cmd = app.add_subcommand("export", "BC4 tables, DDS/KTX2 and the C++ header");
  export_cmd->add_option("--fit", exporter.fit, "fit.json from gtbake fit")->required();
  export_cmd->add_option("--gtso", exporter.gtso, "Directory from gtbake gtso")->required();
  export_cmd->add_option("--out", exporter.out, "Output directory")->required();
  export_cmd->add_option("--threads", exporter.threads, "Worker threads (0 = all cores)");
  export_cmd->add_option("--validate-gtso", exporter.validate_gtso,
                         "validate_gtso.json whose u (fitted to path-traced S) the header ships");

  AllOptions all;
  auto* all_cmd = app.add_subcommand("all", "scenes, sweep, fit, gtso and export with defaults");
  all_cmd->add_option("--out", all.out, "Output directory")->capture_default_str();
  all_cmd->add_option("--threads", all.threads, "Worker threads (0 = all cores)");

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

  const bool progress = !quiet;
  try {
    if (*scenes_cmd) {
      scenes.progress = progress;
      runScenes(scenes);
    } else if (*sweep_cmd) {
      std::tie(sweep.width, sweep.height) = parseResolution(resolution);
      sweep.specular_roughness = parseSpecularRoughness(specular_roughness);
      sweep.progress = progress;
      runSweep(sweep);
    } else if (*fit_cmd) {
      if (!fit_shipped.empty()) fit.shipped = parseCoeffs(fit_shipped);
      fit.progress = progress;
      runFit(fit);
    } else if (*validate_cmd) {
      if (!validate_coeffs.empty()) validate.coeffs = parseCoeffs(validate_coeffs);
      validate.progress = progress;
      runValidate(validate);
    } else if (*gtso_cmd) {
      gtso.progress = progress;
      runGtso(gtso);
    } else if (*validate_gtso_cmd) {
      validate_gtso.progress = progress;
      runValidateGtso(validate_gtso);
    } else if (*export_cmd) {
      exporter.command_line = joinArguments(argc, argv);
      exporter.progress = progress;
      runExport(exporter);
    } else if (*all_cmd) {
      // The output directory and thread count do not change a byte of the results, so the
      // provenance records the canonical command and luts/ reproduces from any --out.
      all.command_line = "gtbake all";
      all.progress = progress;
      runAll(all);
    }
  } catch (const gtbake::Error& e) {
    std::fprintf(stderr, "gtbake: error: %s\n", firstLine(e.what()).c_str());
    return kExitError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gtbake: internal error: %s\n", firstLine(e.what()).c_str());
    return kExitError;
  }
  return 0;
}
