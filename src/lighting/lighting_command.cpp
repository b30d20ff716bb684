#include "lighting/lighting_command.h"

#include <set>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/output_lock.h"
#include "common/output_set.h"
#include "fit/fit_set.h"

namespace gtbake {

void runLighting(const LightingOptions& o) {
  if (o.sweep.empty()) throw Error("no sweep directory given: pass --sweep DIR");
  if (o.out.empty()) throw Error("no output directory given: pass --out DIR");
  if (o.environments.empty()) throw Error("no environment given: pass --env FILE|CLASS");
  // Every environment read before anything is written.
  std::vector<Environment> environments;
  std::set<std::string> names;
  for (const std::string& argument : o.environments) {
    environments.push_back(environmentFromArgument(argument));
    if (!names.insert(environments.back().name).second) {
      throw Error("two environments are named '" + environments.back().name + "'");
    }
  }
  std::optional<MultiBounceCoeffs> fit;
  if (!o.fit.empty()) fit = readFitInput(o.fit).linear;
  const OutputLock lock(o.out);  // for the whole run (output_lock.h)
  const LightingAnalysis analysis = analyzeLighting(o.sweep, environments, fit, o.progress);
  OutputSet output(o.out, "lighting");
  nlohmann::ordered_json settings;
  settings["sweep"] = relativePath(o.sweep, o.out);
  settings["environments"] = o.environments;
  settings["fit"] = o.fit.empty() ? "" : relativePath(o.fit, o.out);
  output.setSettings(settings);
  output.add("lighting.json",
             lightingJson(analysis, settings["sweep"], settings["fit"]).dump(2) + "\n");
  output.add("lighting.html", lightingReportHtml(analysis));
  for (const EnvironmentResult& e : analysis.environments) {
    for (const auto& [name, png] : e.images) output.add(name, png);
  }
  output.commit();
  if (o.print_summary) printLightingSummary(analysis);
}

}  // namespace gtbake
