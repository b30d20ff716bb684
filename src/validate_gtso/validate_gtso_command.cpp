// `gtbake validate-gtso`: read the sweep and the tables, evaluate every method at every pixel and
// roughness, fit u (validate_gtso_analysis.h), then write validate_gtso.json, the per-scene image
// rows and the HTML page (validate_gtso_outputs.h) and print the one-screen summary.
#include "validate_gtso/validate_gtso_command.h"

#include <chrono>
#include <string>

#include "common/error.h"
#include "common/output_layout.h"
#include "common/output_lock.h"
#include "common/output_set.h"
#include "common/text_format.h"
#include "validate_gtso/validate_gtso_analysis.h"
#include "validate_gtso/validate_gtso_outputs.h"

namespace gtbake {

namespace fs = std::filesystem;

ValidateGtsoResult runValidateGtso(const ValidateGtsoOptions& options) {
  if (options.sweep.empty()) throw Error("validate-gtso: --sweep DIR is required");
  if (options.luts.empty()) throw Error("validate-gtso: --luts DIR is required");
  if (options.u != 0.0 && !(options.u > 0.0 && options.u < 1.0)) {
    throw Error("validate-gtso: --u must lie in (0, 1), got " + formatNumber(options.u, "%g"));
  }
  if (options.u != 0.0 && !options.input.rayTraced()) {
    throw Error("validate-gtso: --u scores the ray-traced inputs; leave it out with --estimator");
  }
  const auto start = std::chrono::steady_clock::now();
  // On an estimator's inputs the results sit beside its profile (docs/profiles.md).
  const fs::path out = !options.out.empty() ? options.out
                       : options.input.rayTraced()
                           ? options.luts / kValidateGtsoDir
                           : options.luts / kProfilesDir / options.input.estimator;
  const OutputLock lock(out);  // for the whole run (output_lock.h)
  // Read and compute everything before writing anything.
  const Analysis a = analyse(options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const nlohmann::ordered_json json = validateGtsoJson(options, out, a, seconds);

  // The page and its images are part of the set (report/ beside validate_gtso.json): a failed
  // run leaves the previous page with the previous JSON.
  const fs::path json_path = out / "validate_gtso.json";
  OutputSet output(out, "validate_gtso");  // export requires and verifies it
  addValidateGtsoReport(a, options.write_images, output);
  output.add(json_path.filename().string(), json.dump(2) + "\n");
  output.commit();
  if (options.print_summary) printValidateGtsoSummary(a, json_path);

  ValidateGtsoResult result;
  result.json = json_path;
  result.u = a.spec.all.u;
  result.u_low = a.scene_stats.u.interval[0].low;
  result.u_high = a.scene_stats.u.interval[0].high;
  result.seconds = seconds;
  for (Method m : a.methods) {
    result.rmse.emplace_back(methodName(m), a.t.overall[static_cast<int>(m)].rmse());
  }
  return result;
}

}  // namespace gtbake
