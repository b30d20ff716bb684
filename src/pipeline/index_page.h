// <out>/index.html of `gtbake all`: a link to every report and result of the layout
// (docs/reproducibility.md "Layout"), relative, so the directory can be moved or served as is.
#pragma once

#include <filesystem>
#include <string>

namespace gtbake {

// The page for the files under `out` (every *.html page, every stage's JSON result,
// ship/README.md), listed by folder in name order: the same tree gives the same bytes.
std::string indexPage(const std::filesystem::path& out);

// Writes indexPage(out) as <out>/index.html, an output set of its own (index.manifest.json).
void writeIndexPage(const std::filesystem::path& out);

}  // namespace gtbake
