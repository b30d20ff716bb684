#include "pipeline/index_page.h"

#include <map>
#include <set>
#include <vector>

#include "common/output_set.h"
#include "common/text_escape.h"
#include "gtbake_version.h"

namespace gtbake {

namespace fs = std::filesystem;

namespace {

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// What the index links: reports (HTML), results (JSON other than manifests and inputs a stage
// reads back), and ship/README.md; the scene corpus and the index itself are not listed.
bool listed(const std::string& relative) {
  if (relative == "index.html" || relative.rfind("scenes/", 0) == 0) return false;
  if (endsWith(relative, ".manifest.json")) return false;
  return endsWith(relative, ".html") || endsWith(relative, ".json") || relative == "ship/README.md";
}

}  // namespace

std::string indexPage(const fs::path& out, const std::map<std::string, std::string>& also) {
  std::set<std::string> names;
  for (const auto& entry : fs::recursive_directory_iterator(out)) {
    if (entry.is_regular_file())
      names.insert(entry.path().lexically_relative(out).generic_string());
  }
  for (const auto& [name, bytes] : also) names.insert(name);
  std::map<std::string, std::vector<std::string>> by_folder;  // folder -> files, both sorted
  for (const std::string& relative : names) {
    if (!listed(relative)) continue;
    const std::size_t slash = relative.find('/');
    by_folder[slash == std::string::npos ? "" : relative.substr(0, slash)].push_back(relative);
  }
  std::string html =
      "<!DOCTYPE html>\n<html><head><meta charset='utf-8'><title>gtbake outputs</title>\n"
      "<style>body{font-family:sans-serif;margin:24px;max-width:1000px}</style></head><body>\n"
      "<h1>gtbake outputs</h1>\n<p>One folder per stage, each with its outputs and its manifest; "
      "ship/ holds what an engine ships. Reports (.html) and results (.json) of this directory. "
      "gtbake " GTBAKE_VERSION ".</p>\n";
  for (const auto& [folder, files] : by_folder) {
    html += "<h2>" + escapeHtml(folder.empty() ? "." : folder + "/") + "</h2>\n<ul>\n";
    for (const std::string& f : files) {
      html += "<li><a href=\"" + escapeHtml(f) + "\">" + escapeHtml(f) + "</a></li>\n";
    }
    html += "</ul>\n";
  }
  return html + "</body></html>\n";
}

void writeIndexPage(const fs::path& out) {
  OutputSet set(out, "index");
  set.add("index.html", indexPage(out));
  set.commit();
}

}  // namespace gtbake
