// gtbake-docs: keeps the numbers docs quote from artifacts equal to the artifacts.
//
//   gtbake-docs --check  [--luts DIR] [--data DIR] PATH...   list every mismatch, missing value
//                                     and malformed marker as FILE:LINE: message; exit 1 if any
//   gtbake-docs --update [--luts DIR] [--data DIR] PATH...   rewrite the quoted numbers in place
//                                     (atomically, per file); exit 1 if a marker cannot be resolved
//
// PATH is a Markdown file or a directory (its *.md files, recursively, in sorted order). The
// marker syntax is in src/docs/doc_numbers.h and docs/index.md.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "common/atomic_file.h"
#include "common/error.h"
#include "docs/doc_numbers.h"
#include "docs/ranking_block.h"
#include "docs/verdict_block.h"

namespace {

namespace fs = std::filesystem;

constexpr int kExitIssues = 1;  // a mismatch, a missing value or a malformed marker
constexpr int kExitUsage = 2;   // the command line itself did not parse

std::vector<fs::path> markdownFiles(const std::vector<std::string>& paths) {
  std::vector<fs::path> files;
  for (const std::string& arg : paths) {
    const fs::path path(arg);
    if (fs::is_directory(path)) {
      std::vector<fs::path> found;
      for (const auto& entry : fs::recursive_directory_iterator(path)) {
        if (entry.is_regular_file() && entry.path().extension() == ".md") {
          found.push_back(entry.path());
        }
      }
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(path)) {
      files.push_back(path);
    } else {
      throw gtbake::Error(arg + ": no such file or directory");
    }
  }
  return files;
}

// The generated blocks a document may hold, each rebuilt from its artifact in luts/: the ranking
// list (docs/validate_gtso.md §2, validate_gtso.json) and the verdict by range of A (docs/fit.md
// §5, fit.json). Sets them in `text`; without --update a block that differs is a problem.
int setGeneratedBlocks(const fs::path& file, const std::string& luts, bool update,
                       std::string& text) {
  struct Block {
    const char* tag;
    const char* artifact;
    std::string (*lines)(const nlohmann::json&);
  };
  const Block blocks[] = {
      {"ranking-tests", "validate_gtso/validate_gtso.json", gtbake::docs::rankingLines},
      {"shipped-verdict", "fit/fit.json", gtbake::docs::verdictLines}};
  int issues = 0;
  for (const Block& b : blocks) {
    if (text.find(std::string("<!-- ") + b.tag + ":begin -->") == std::string::npos) continue;
    const std::string lines =
        b.lines(nlohmann::json::parse(gtbake::readFile(fs::path(luts) / b.artifact)));
    const auto block = gtbake::docs::withGeneratedBlock(text, b.tag, lines);
    if (block && *block != text && !update) {
      std::fprintf(stderr, "%s: the %s block differs from %s/%s\n", file.string().c_str(), b.tag,
                   luts.c_str(), b.artifact);
      ++issues;
    }
    if (block) text = *block;
  }
  return issues;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"gtbake-docs: check or update the numbers docs quote from artifacts"};
  bool check = false;
  bool update = false;
  std::string luts = "luts";
  std::string data = "data";
  std::vector<std::string> paths;
  auto* check_flag = app.add_flag("--check", check, "Report every number that disagrees");
  app.add_flag("--update", update, "Rewrite the numbers to the artifacts' values")
      ->excludes(check_flag);
  app.add_option("--luts", luts, "Artifact directory the markers' files are relative to")
      ->capture_default_str();
  app.add_option("--data", data, "Directory of the committed studies markers name as data/...")
      ->capture_default_str();
  app.add_option("paths", paths, "Markdown files or directories")->required();
  try {
    app.parse(argc, argv);
    if (!check && !update) throw CLI::ValidationError("one of --check or --update is required");
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::string what = e.what();
    std::fprintf(stderr, "gtbake-docs: error: %s\n", what.substr(0, what.find('\n')).c_str());
    return kExitUsage;
  }

  try {
    const gtbake::docs::ValueLookup lookup = gtbake::docs::jsonLookup(luts, data);
    int markers = 0;
    int issues = 0;
    int rewritten = 0;
    const std::vector<fs::path> files = markdownFiles(paths);
    for (const fs::path& file : files) {
      const std::string text = gtbake::readFile(file);
      const gtbake::docs::CheckResult result = gtbake::docs::checkDocument(text, lookup);
      markers += result.markers;
      for (const gtbake::docs::DocIssue& issue : result.issues) {
        // An update fixes the mismatches; report only what is left.
        if (update && issue.kind == gtbake::docs::DocIssue::Kind::kMismatch) continue;
        std::fprintf(stderr, "%s:%d: %s\n", file.string().c_str(), issue.line,
                     issue.message.c_str());
        ++issues;
      }
      std::string updated = result.updated_text;
      issues += setGeneratedBlocks(file, luts, update, updated);
      if (update && updated != text) {
        gtbake::writeFileAtomically(file, updated);
        std::printf("gtbake-docs: updated %d number(s) in %s\n", result.mismatches,
                    file.string().c_str());
        ++rewritten;
      }
    }
    std::printf("gtbake-docs: %d marker(s) in %zu file(s), %d problem(s)", markers, files.size(),
                issues);
    if (update) std::printf(", %d file(s) rewritten", rewritten);
    std::printf("\n");
    return issues == 0 ? 0 : kExitIssues;
  } catch (const gtbake::Error& e) {
    std::fprintf(stderr, "gtbake-docs: error: %s\n", e.what());
    return kExitIssues;
  }
}
