// <out>/index.html of `gtbake all`: a link to every report and result of the layout
// (docs/reproducibility.md "Layout"), relative, so the directory can be moved or served as is.
#pragma once

#include <filesystem>
#include <map>
#include <string>

namespace gtbake {

// The page for the files under `out` and the names in `also` (relative to out: the pages `gtbake
// report` is about to write), linking every *.html page, every stage's JSON result and
// ship/README.md, by folder in name order: the same names give the same bytes.
std::string indexPage(const std::filesystem::path& out,
                      const std::map<std::string, std::string>& also = {});

// Writes indexPage(out) as <out>/index.html, an output set of its own (index.manifest.json).
void writeIndexPage(const std::filesystem::path& out);

}  // namespace gtbake
