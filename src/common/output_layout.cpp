#include "common/output_layout.h"

#include <string>

#include "common/error.h"

namespace gtbake {

void refuseFlatLayout(const std::filesystem::path& dir, const char* command) {
  // What the flat layout put at the top: the sweep, fit, encode, validate-gtso and export sets,
  // and the fit report (left behind in a checkout whose tracked files moved to the new layout).
  for (const char* name : {"sweep.json", "sweep.manifest.json", "fit.json", "fit.manifest.json",
                           "encode.manifest.json", "validate_gtso.manifest.json",
                           "export.manifest.json", "gtbake_tables.h", "report/index.html"}) {
    std::error_code ec;
    if (!std::filesystem::exists(dir / name, ec)) continue;
    throw Error(std::string(command) + ": " + dir.string() + " holds the flat layout of an older " +
                "gtbake (" + name + " at its top); give --out a new directory or remove that one " +
                "(docs/reproducibility.md \"Layout\")");
  }
}

}  // namespace gtbake
