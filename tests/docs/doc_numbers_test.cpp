// The docs-number markers: parsing, the check, the update, and the command-line tool end to end.
#include "docs/doc_numbers.h"
#include "docs/ranking_block.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <map>
#include <string>

#include "common/atomic_file.h"
#include "common/error.h"
#include "support/temp_dir.h"

namespace gtbake::docs {
namespace {

// A lookup over a fixed table, so the parser and checker are tested without files.
ValueLookup fakeLookup(std::map<std::string, double> values) {
  return [values](const std::string& file, const std::string& pointer) {
    LookupResult result;
    const auto it = values.find(file + " " + pointer);
    if (it == values.end()) {
      result.error = file + " has no " + pointer;
    } else {
      result.value = it->second;
    }
    return result;
  };
}

TEST(DocNumbers, ParsesFieldsNumberAndLine) {
  const std::string text = "intro\na1 = 2.3990<!--@ fit.json /linear/a1 %.4f--> and\n";
  const ParsedDoc doc = parseMarkers(text);
  ASSERT_TRUE(doc.malformed.empty());
  ASSERT_EQ(doc.markers.size(), 1u);
  const NumberMarker& m = doc.markers[0];
  EXPECT_EQ(m.line, 2);
  EXPECT_EQ(m.quoted, "2.3990");
  EXPECT_EQ(text.substr(m.number_begin, m.number_end - m.number_begin), "2.3990");
  EXPECT_EQ(m.file, "fit.json");
  EXPECT_EQ(m.pointer, "/linear/a1");
  EXPECT_EQ(m.format, "%.4f");
  EXPECT_EQ(m.scale, 1.0);
}

TEST(DocNumbers, MatchingNumbersPass) {
  const std::string text =
      "a 2.3990<!--@ fit.json /linear/a1 %.4f-->, b \xE2\x88\x92"
      "0.3614<!--@ fit.json /linear/a0 %.4f-->, c 19<!--@ s.json /share %.0f x100-->%, "
      "d 8.0e-05<!--@ g.json /u %.1e-->, e +0.36<!--@ fit.json /d %+.2f-->\n";
  const CheckResult r = checkDocument(text, fakeLookup({{"fit.json /linear/a1", 2.398975942},
                                                        {"fit.json /linear/a0", -0.36138},
                                                        {"s.json /share", 0.19},
                                                        {"g.json /u", 7.985e-5},
                                                        {"fit.json /d", 0.3586}}));
  EXPECT_EQ(r.markers, 5);
  EXPECT_TRUE(r.issues.empty()) << r.issues[0].message;
  EXPECT_EQ(r.updated_text, text);
}

TEST(DocNumbers, MismatchIsReportedAndUpdateFixesIt) {
  const std::string text =
      "line one\n| a1 | 2.3990<!--@ fit.json /linear/a1 %.4f--> |\n"
      "| a0 | \xE2\x88\x92"
      "0.3614<!--@ fit.json /linear/a0 %.4f--> | 1.5<!--@ fit.json /linear/a1 %.1f-->\n";
  const ValueLookup lookup =
      fakeLookup({{"fit.json /linear/a1", 2.41236}, {"fit.json /linear/a0", -0.30012}});
  const CheckResult r = checkDocument(text, lookup);
  EXPECT_EQ(r.markers, 3);
  EXPECT_EQ(r.mismatches, 3);
  ASSERT_EQ(r.issues.size(), 3u);
  EXPECT_EQ(r.issues[0].kind, DocIssue::Kind::kMismatch);
  EXPECT_EQ(r.issues[0].line, 2);
  EXPECT_NE(r.issues[0].message.find("reads 2.3990"), std::string::npos) << r.issues[0].message;
  EXPECT_NE(r.issues[0].message.find("gives 2.4124"), std::string::npos) << r.issues[0].message;
  EXPECT_EQ(r.issues[1].line, 3);
  EXPECT_EQ(r.issues[2].line, 3);
  // The update keeps everything but the numbers, including the doc's U+2212 minus.
  EXPECT_EQ(r.updated_text,
            "line one\n| a1 | 2.4124<!--@ fit.json /linear/a1 %.4f--> |\n"
            "| a0 | \xE2\x88\x92"
            "0.3001<!--@ fit.json /linear/a0 %.4f--> | 2.4<!--@ fit.json /linear/a1 %.1f-->\n");
  const CheckResult again = checkDocument(r.updated_text, lookup);
  EXPECT_TRUE(again.issues.empty());
  EXPECT_EQ(again.updated_text, r.updated_text);
}

TEST(DocNumbers, LastDigitDifferenceIsAMismatch) {
  const CheckResult r =
      checkDocument("x 0.0131<!--@ fit.json /v %.4f-->", fakeLookup({{"fit.json /v", 0.01306541}}));
  EXPECT_EQ(r.mismatches, 0);
  const CheckResult off =
      checkDocument("x 0.0130<!--@ fit.json /v %.4f-->", fakeLookup({{"fit.json /v", 0.01306541}}));
  EXPECT_EQ(off.mismatches, 1);
}

TEST(DocNumbers, MalformedMarkersAreRejectedWithTheirLine) {
  const struct {
    const char* text;
    const char* reason;
  } cases[] = {
      {"1.0<!--@ fit.json /a-->", "got 2 fields"},
      {"1.0<!--@ fit.json /a %.1f x100 extra-->", "got 5 fields"},
      {"1.0<!--@ fit.json a %.1f-->", "not an RFC 6901"},
      {"1.0<!--@ fit.json /a/~2 %.1f-->", "not an RFC 6901"},
      {"1.0<!--@ fit.json /a %d-->", "needs one conversion"},
      {"1.0<!--@ fit.json /a %d-->", "needs one conversion"},
      {"1.0<!--@ fit.json /a %.1f%%-->", "text after the conversion"},
      {"1.0<!--@ fit.json /a .1f-->", "must start with %"},
      {"1.0<!--@ fit.json /a %.1f 100-->", "SCALE"},
      {"1.0<!--@ /abs/fit.json /a %.1f-->", "relative"},
      {"1.0<!--@ ../fit.json /a %.1f-->", "relative"},
      {"1.0<!--@ fit.json /a %.1f", "not closed"},
      {"1.0<!--@ fit.json /a %.1f\n-->", "not closed"},
      {"none <!--@ fit.json /a %.1f-->", "no number"},
      {"G050<!--@ fit.json /a %.1f-->", "glued"},
      {"258,048<!--@ fit.json /a %.0f-->", "glued"},
  };
  for (const auto& c : cases) {
    const std::string text = std::string("first line\n") + c.text + "\n";
    const CheckResult r = checkDocument(text, fakeLookup({{"fit.json /a", 1.0}}));
    ASSERT_EQ(r.issues.size(), 1u) << c.text;
    EXPECT_EQ(r.issues[0].kind, DocIssue::Kind::kMalformed) << c.text;
    EXPECT_EQ(r.issues[0].line, 2) << c.text;
    EXPECT_NE(r.issues[0].message.find(c.reason), std::string::npos)
        << c.text << " -> " << r.issues[0].message;
    EXPECT_EQ(r.updated_text, text) << c.text;
  }
}

// A "%s" marker quotes a JSON string as one word (a status), checked and updated like a number;
// a number where a word is expected, or a word where a number is, is a lookup issue.
TEST(DocNumbers, WordMarkersQuoteStrings) {
  const ValueLookup lookup = [](const std::string& file, const std::string& pointer) {
    LookupResult r;
    if (pointer == "/status") r.text = "upper_bound";
    if (pointer == "/value") r.value = 4.0;
    if (!r.text && !r.value) r.error = file + " has no " + pointer;
    return r;
  };
  const std::string text =
      "| interior<!--@ tune.json /status %s--> | 4.0<!--@ tune.json /value %.1f--> |\n";
  const CheckResult r = checkDocument(text, lookup);
  EXPECT_EQ(r.markers, 2);
  EXPECT_EQ(r.mismatches, 1);
  EXPECT_EQ(r.updated_text,
            "| upper_bound<!--@ tune.json /status %s--> | 4.0<!--@ tune.json /value %.1f--> |\n");
  EXPECT_TRUE(checkDocument(r.updated_text, lookup).issues.empty());
  const CheckResult wrong = checkDocument("x 4<!--@ tune.json /value %s-->\n", lookup);
  ASSERT_EQ(wrong.issues.size(), 1u);
  EXPECT_NE(wrong.issues[0].message.find("not a string"), std::string::npos);
}

TEST(DocNumbers, ExamplesInCodeAreNotMarkers) {
  const std::string text =
      "Syntax `1.0<!--@ FILE POINTER FORMAT-->` in a span\n"
      "```\n"
      "2.0<!--@ fit.json /a %.1f-->\n"
      "  ```\n"
      "after the fence 1.0<!--@ fit.json /a %.1f--> and `x` 3.0<!--@ fit.json /a %.1f-->\n";
  const CheckResult r = checkDocument(text, fakeLookup({{"fit.json /a", 1.0}}));
  EXPECT_EQ(r.markers, 2);
  ASSERT_EQ(r.issues.size(), 1u);
  EXPECT_EQ(r.issues[0].line, 5);
  EXPECT_NE(r.issues[0].message.find("reads 3.0"), std::string::npos) << r.issues[0].message;
}

TEST(DocNumbers, FormatNumberIsPrintf) {
  EXPECT_EQ(formatNumber("%.4f", 2.398975942683847), "2.3990");
  EXPECT_EQ(formatNumber("%.3g", 1.56e-4), "0.000156");
  EXPECT_EQ(formatNumber("%.2e", 1.56e-4), "1.56e-04");
  EXPECT_EQ(formatNumber("%.0f", 36864.0), "36864");
  EXPECT_EQ(formatNumber("%+.4f", -0.029), "-0.0290");
  EXPECT_THROW(formatNumber("%.4f %.4f", 1.0), Error);
}

TEST(DocNumbers, JsonLookupReportsMissingFilePointerAndNonNumbers) {
  const test::TempDir dir("docs-lookup");
  writeFileAtomically(
      dir.path() / "fit.json",
      R"({"linear": {"a1": 2.5, "name": "x", "none": null, "ok": true}, "list": [1, 7]})");
  writeFileAtomically(dir.path() / "bad.json", "{not json");
  const ValueLookup lookup = jsonLookup(dir.path());
  EXPECT_EQ(lookup("fit.json", "/linear/a1").value, 2.5);
  EXPECT_EQ(lookup("fit.json", "/list/1").value, 7.0);
  const LookupResult missing_key = lookup("fit.json", "/linear/b1");
  EXPECT_FALSE(missing_key.value);
  EXPECT_NE(missing_key.error.find("has no /linear/b1"), std::string::npos) << missing_key.error;
  EXPECT_NE(lookup("fit.json", "/list/5").error.find("has no"), std::string::npos);
  EXPECT_EQ(lookup("fit.json", "/linear/name").text, std::optional<std::string>("x"));
  EXPECT_NE(lookup("fit.json", "/linear/name").error.find("string, not a number"),
            std::string::npos);
  EXPECT_NE(lookup("fit.json", "/linear/none").error.find("null, not a number"), std::string::npos);
  EXPECT_EQ(lookup("fit.json", "/linear/ok").text, std::optional<std::string>("true"));
  EXPECT_FALSE(lookup("fit.json", "/linear/ok").value);
  EXPECT_NE(lookup("gone.json", "/a").error.find("gone.json"), std::string::npos);
  EXPECT_NE(lookup("bad.json", "/a").error.find("not valid JSON"), std::string::npos);
}

// "data/..." reads the data directory (the committed studies outside luts/), everything else the
// artifact directory; without a data directory "data/..." is just a path under the artifacts.
TEST(DocNumbers, JsonLookupReadsDataFilesFromTheDataDirectory) {
  const test::TempDir dir("docs-data");
  std::filesystem::create_directories(dir.path() / "luts" / "data" / "study");
  std::filesystem::create_directories(dir.path() / "data" / "study");
  writeFileAtomically(dir.path() / "luts" / "fit.json", R"({"x": 1})");
  writeFileAtomically(dir.path() / "luts" / "data" / "study" / "fit.json", R"({"x": 2})");
  writeFileAtomically(dir.path() / "data" / "study" / "fit.json", R"({"x": 3})");
  const ValueLookup both = jsonLookup(dir.path() / "luts", dir.path() / "data");
  EXPECT_EQ(both("fit.json", "/x").value, 1.0);
  EXPECT_EQ(both("data/study/fit.json", "/x").value, 3.0);
  EXPECT_NE(both("data/gone.json", "/x").error.find((dir.path() / "data").string()),
            std::string::npos);
  EXPECT_EQ(jsonLookup(dir.path() / "luts")("data/study/fit.json", "/x").value, 2.0);
}

// The tool as CTest and scripts/regen-luts.sh run it.
int runTool(const std::string& arguments, const test::TempDir& dir) {
  const std::string command = std::string(GTBAKE_DOCS_BINARY) + " " + arguments + " >" +
                              (dir.path() / "stdout").string() + " 2>" +
                              (dir.path() / "stderr").string();
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(DocNumbersTool, CheckListsProblemsUpdateFixesMismatchesAtomically) {
  const test::TempDir dir("docs-tool");
  std::filesystem::create_directories(dir.path() / "luts" / "gtso");
  std::filesystem::create_directories(dir.path() / "docs");
  writeFileAtomically(dir.path() / "luts" / "fit.json", R"({"linear": {"a1": 2.41236}})");
  writeFileAtomically(dir.path() / "luts" / "gtso" / "gtso.json", R"({"cone": {"u": 7.985e-5}})");
  const std::filesystem::path doc = dir.path() / "docs" / "index.md";
  writeFileAtomically(doc,
                      "# t\na1 = 2.3990<!--@ fit.json /linear/a1 %.4f-->\n"
                      "u = 8.0e-05<!--@ gtso/gtso.json /cone/u %.1e-->\n");
  const std::string args =
      "--luts " + (dir.path() / "luts").string() + " " + (dir.path() / "docs").string();

  EXPECT_EQ(runTool("--check " + args, dir), 1);
  const std::string err = test::readBytes(dir.path() / "stderr");
  EXPECT_NE(err.find("index.md:2: reads 2.3990 but fit.json /linear/a1 %.4f gives 2.4124"),
            std::string::npos)
      << err;
  EXPECT_EQ(err.find("index.md:3"), std::string::npos) << err;

  EXPECT_EQ(runTool("--update " + args, dir), 0) << test::readBytes(dir.path() / "stderr");
  EXPECT_EQ(test::readBytes(doc),
            "# t\na1 = 2.4124<!--@ fit.json /linear/a1 %.4f-->\n"
            "u = 8.0e-05<!--@ gtso/gtso.json /cone/u %.1e-->\n");
  for (const auto& entry : std::filesystem::directory_iterator(dir.path() / "docs")) {
    EXPECT_EQ(entry.path().filename(), "index.md");  // no temporary file left behind
  }
  EXPECT_EQ(runTool("--check " + args, dir), 0) << test::readBytes(dir.path() / "stderr");

  // A marker that cannot be resolved fails both modes and leaves the file as it was.
  writeFileAtomically(doc, "x 1.0<!--@ fit.json /linear/b1 %.1f-->\n");
  EXPECT_EQ(runTool("--update " + args, dir), 1);
  EXPECT_NE(test::readBytes(dir.path() / "stderr").find("index.md:1: fit.json has no /linear/b1"),
            std::string::npos);
  EXPECT_EQ(test::readBytes(doc), "x 1.0<!--@ fit.json /linear/b1 %.1f-->\n");
  EXPECT_EQ(runTool("--check --update " + args, dir), 2);
  EXPECT_EQ(runTool(args, dir), 2);
  EXPECT_EQ(runTool("--check " + (dir.path() / "nowhere").string(), dir), 1);
}

// The ranking list is rebuilt from validate_gtso.json in roughness order, between its markers only.
TEST(RankingBlock, LinesComeFromTheStatementsInRoughnessOrder) {
  const nlohmann::json j = nlohmann::json::parse(R"({
    "sweep": {"roughness": [0.1, 0.25]},
    "ranking_tests": {"by_roughness": {"S025": {"statement": "B wins."},
                                       "S010": {"statement": "A ties."}}}})");
  const std::string lines = rankingLines(j);
  EXPECT_EQ(lines, "- r_p 0.10: A ties.\n- r_p 0.25: B wins.\n");
  const std::string doc = "x\n<!-- ranking-tests:begin -->\n- old\n<!-- ranking-tests:end -->\ny\n";
  EXPECT_EQ(withRankingBlock(doc, lines),
            "x\n<!-- ranking-tests:begin -->\n" + lines + "<!-- ranking-tests:end -->\ny\n");
  EXPECT_FALSE(withRankingBlock("x\n<!-- ranking-tests:begin -->\n- old\n", lines));
  EXPECT_THROW(rankingLines(nlohmann::json::object()), Error);
}

}  // namespace
}  // namespace gtbake::docs
