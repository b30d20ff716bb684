#include "pipeline/report_command.h"

#include <unistd.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/output_layout.h"
#include "common/output_lock.h"
#include "common/output_set.h"
#include "common/threads.h"
#include "fit/fit_command.h"
#include "gtso/gtso_command.h"
#include "gtso/gtso_set.h"
#include "lighting/environment.h"
#include "lighting/lighting_command.h"
#include "pipeline/index_page.h"
#include "screen_ao/screen_ao_command.h"
#include "tune/tune_analysis.h"
#include "tune/tune_command.h"
#include "validate_gtso/validate_gtso_command.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

// Files relative to the output directory ("fit/report/index.html") and their bytes.
using Files = std::map<std::string, std::string>;

bool isPicture(const std::string& name) {
  const std::string ext = fs::path(name).extension().string();
  return ext == ".png" || ext == ".svg" || ext == ".html";
}

// The scratch directory the stages write into, removed whatever happens.
class Scratch {
 public:
  explicit Scratch(const fs::path& out)
      : dir_(fs::temp_directory_path() /
             ("gtbake-report-" + std::to_string(::getpid()) + "-" + out.filename().string())) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  const fs::path& dir() const { return dir_; }

 private:
  fs::path dir_;
};

// The pictures and pages of the set `command` in scratch/folder, under folder/ in `files`.
void takePictures(const fs::path& scratch, const std::string& folder, const std::string& command,
                  Files* files) {
  const OutputManifest set = readOutputSet(scratch / folder, command);
  for (const OutputFile& f : set.files) {
    if (isPicture(f.name)) (*files)[folder + "/" + f.name] = set.readVerified(f.name);
  }
}

// The sweep's previews (<view>_A.png, <view>_G050.png) from the channels of its verified EXRs,
// drawn as the sweep draws them (8-bit gray over [0, 1]).
void sweepPreviews(const fs::path& luts, Files* files) {
  const OutputManifest set = readOutputSet(luts / kSweepDir, "sweep");
  std::string decoded;  // the EXR last decoded: a view's previews are listed side by side
  std::shared_ptr<const ExrImage> image;
  for (const OutputFile& f : set.files) {
    if (fs::path(f.name).extension() != ".png") continue;
    const std::string stem = fs::path(f.name).stem().string();
    const std::size_t cut = stem.rfind('_');
    if (cut == std::string::npos) {
      throw Error((luts / kSweepDir / f.name).string() + ": not a preview <view>_<channel>.png");
    }
    const std::string exr = stem.substr(0, cut) + ".exr";
    if (exr != decoded) {
      image = readVerifiedExr(set, exr, (luts / kSweepDir / exr).string());
      decoded = exr;
    }
    const std::vector<float>& channel = image->channel(stem.substr(cut + 1), exr);
    (*files)[std::string(kSweepDir) + "/" + f.name] =
        encodePng(image->width, image->height, 1, toGray8(channel, 0.0f, 1.0f));
  }
}

// The gtso slices from the verified .f32 tables.
void gtsoPreviews(const fs::path& luts, const fs::path& scratch, Files* files) {
  const GtsoInput gtso = readGtsoInput(luts / kGtsoDir);
  OutputSet set(scratch / kGtsoDir, "gtso");
  writeGtsoPreviews(set, gtso.table3d.values, gtso.table4d.values, gtso.table3d.dims[0]);
  set.commit();
  takePictures(scratch, kGtsoDir, "gtso", files);
}

// The fit report, screen-ao's and tune's pages, as `gtbake all` runs them, on the sweep of luts.
void stageReports(const ReportOptions& o, int threads, const fs::path& scratch, Files* files) {
  FitOptions fit;
  fit.sweep = o.luts / kSweepDir;
  fit.out = scratch / kFitDir / "fit.json";
  fit.progress = o.progress;
  fit.print_summary = false;
  runFit(fit);
  takePictures(scratch, kFitDir, "fit", files);

  ScreenAoOptions screen_ao;
  screen_ao.sweep = o.luts / kSweepDir;
  screen_ao.out = scratch / kScreenAoDir;
  screen_ao.threads = threads;
  screen_ao.progress = o.progress;
  runScreenAo(screen_ao);
  takePictures(scratch, kScreenAoDir, "screen_ao", files);

  if (!fs::exists(o.luts / kTuneDir / manifestFileName("tune"))) return;  // tune was skipped
  TuneOptions tune;
  tune.sweep = o.luts / kSweepDir;
  tune.out = scratch / kTuneDir;
  tune.screen_ao = o.luts / kScreenAoDir;
  tune.threads = threads;
  tune.progress = o.progress;
  runTune(tune);
  takePictures(scratch, kTuneDir, "tune", files);
}

// The lighting stage's page and error maps, as `gtbake all` runs it (the built-in classes, the
// fit's constants).
void lightingReport(const ReportOptions& o, const fs::path& scratch, Files* files) {
  if (!fs::exists(o.luts / kLightingDir / manifestFileName("lighting"))) return;
  LightingOptions lighting;
  lighting.sweep = o.luts / kSweepDir;
  lighting.environments = environmentClasses();
  lighting.fit = o.luts / kFitDir / "fit.json";
  lighting.out = scratch / kLightingDir;
  lighting.print_summary = false;
  runLighting(lighting);
  takePictures(scratch, kLightingDir, "lighting", files);
}

// validate-gtso's pages on the ray-traced inputs and on each profile's estimator.
void validateReports(const ReportOptions& o, const fs::path& scratch, Files* files) {
  ValidateGtsoOptions v;
  v.sweep = o.luts / kSweepDir;
  v.luts = o.luts;
  v.out = scratch / kValidateGtsoDir;
  v.print_summary = false;
  v.progress = o.progress;
  runValidateGtso(v);
  takePictures(scratch, kValidateGtsoDir, "validate_gtso", files);
  if (!fs::is_directory(o.luts / kProfilesDir)) return;
  for (const auto& entry : fs::directory_iterator(o.luts / kProfilesDir)) {
    const std::string estimator = entry.path().filename().string();
    if (!fs::exists(entry.path() / manifestFileName("validate_gtso"))) continue;
    ValidateGtsoOptions p = v;
    p.input.estimator = estimator;
    p.input.screen_ao = o.luts / kScreenAoDir;
    p.out = scratch / kProfilesDir / estimator;
    p.write_images = false;  // as gtbake all runs it
    runValidateGtso(p);
    takePictures(scratch, std::string(kProfilesDir) + "/" + estimator, "validate_gtso", files);
  }
}

// Every picture and page a manifest under luts lists, as folder-relative name -> set; checks that
// `files` holds exactly those, each with the SHA-256 its manifest records.
void checkAgainstManifests(const fs::path& luts, const Files& files) {
  std::map<std::string, std::string> listed;  // file -> its manifest
  for (const auto& entry : fs::recursive_directory_iterator(luts)) {
    const std::string name = entry.path().filename().string();
    const std::string suffix = ".manifest.json";
    if (name.size() <= suffix.size() || name.rfind(suffix) != name.size() - suffix.size()) continue;
    const fs::path dir = entry.path().parent_path();
    const OutputManifest set = readOutputSet(dir, name.substr(0, name.size() - suffix.size()));
    const std::string folder = dir.lexically_relative(luts).generic_string();
    for (const OutputFile& f : set.files) {
      if (!isPicture(f.name)) continue;
      const std::string relative = folder == "." ? f.name : folder + "/" + f.name;
      const auto drawn = files.find(relative);
      if (drawn == files.end()) {
        throw Error((luts / relative).string() + ": listed in " + (dir / name).string() +
                    " but not drawn again by gtbake report");
      }
      set.verify(f.name, drawn->second);  // the drawing equals what the run wrote
      listed[relative] = name;
    }
  }
  for (const auto& [relative, bytes] : files) {
    if (listed.count(relative) == 0 && relative != "index.html") {
      throw Error((luts / relative).string() + ": drawn by gtbake report but in no manifest of " +
                  luts.string() + " (rerun gtbake all)");
    }
  }
}

}  // namespace

void runReport(const ReportOptions& options) {
  if (options.luts.empty()) throw Error("report: --luts DIR is required");
  if (options.out.empty()) throw Error("report: --out DIR is required");
  refuseFlatLayout(options.luts, "gtbake report");
  const OutputLock lock(options.out);  // for the whole run (output_lock.h)
  const ThreadLimit limit(options.threads);
  const Scratch scratch(options.out);
  Files files;
  sweepPreviews(options.luts, &files);
  gtsoPreviews(options.luts, scratch.dir(), &files);
  stageReports(options, limit.threads(), scratch.dir(), &files);
  validateReports(options, scratch.dir(), &files);
  lightingReport(options, scratch.dir(), &files);
  // The index of what the directory holds, drawn pictures included.
  files["index.html"] = indexPage(options.luts, files);
  checkAgainstManifests(options.luts, files);
  for (const auto& [relative, bytes] : files) {
    ensureDirectory((options.out / relative).parent_path());
    writeFileAtomically(options.out / relative, bytes);
  }
  if (options.progress) {
    std::fprintf(stderr,
                 "gtbake report: %zu pictures and pages into %s, each as its manifest "
                 "records\n",
                 files.size(), options.out.string().c_str());
  }
}

}  // namespace gtbake
