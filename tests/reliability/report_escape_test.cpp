// Reports escape what they print and file names come from safe slugs (docs/limits.md §Names in
// outputs): a scene named like markup reaches index.html, screen_ao.html and validate_gtso.html
// only as text, and no output file carries its name.
#include <gtest/gtest.h>

#include <set>

#include "common/text_escape.h"
#include "fit/fit_command.h"
#include "reliability_fixtures.h"
#include "screen_ao/screen_ao_command.h"
#include "validate_gtso/validate_gtso_command.h"

namespace gtbake {
namespace {

namespace fs = std::filesystem;
using test::readBytes;
using test::TempDir;

constexpr const char* kHostile = "<img src=x onerror=alert(1)>";

TEST(ReportEscape, EscapesMarkupQuotesAndBadBytes) {
  EXPECT_EQ(escapeHtml(kHostile), "&lt;img src=x onerror=alert(1)&gt;");
  EXPECT_EQ(escapeHtml("a&b\"c'd"), "a&amp;b&quot;c&#39;d");
  EXPECT_EQ(escapeHtml("r\xC3\xA9sum\xC3\xA9"), "r\xC3\xA9sum\xC3\xA9");
  EXPECT_EQ(escapeHtml("x\xFFy\x01"), "x\xEF\xBF\xBDy\xEF\xBF\xBD");
}

TEST(ReportEscape, SlugsAreSafeUniqueAndDeterministic) {
  EXPECT_EQ(fileSlug("cavity_0"), "cavity_0");  // corpus names are kept
  const std::vector<std::string> names = {kHostile,
                                          "<img src=y onerror=alert(1)>",
                                          "../etc",
                                          ".hidden",
                                          "-rf",
                                          "a/b",
                                          "a_b",
                                          "\xFF\xFE",
                                          std::string(300, 'x'),
                                          std::string(300, 'x') + "y",
                                          ""};
  std::set<std::string> slugs;
  for (const std::string& n : names) {
    const std::string s = fileSlug(n);
    EXPECT_EQ(s, fileSlug(n));
    EXPECT_TRUE(slugs.insert(s).second) << n << " -> " << s;
    EXPECT_EQ(
        s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-"),
        std::string::npos)
        << s;
    EXPECT_NE(s[0], '.');
    EXPECT_NE(s[0], '-');
    EXPECT_LE(s.size(), kMaxSlugLength + 9);
  }
}

TEST(ReportEscape, Utf8IsValidatedStrictly) {
  EXPECT_TRUE(isValidUtf8("plain \xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80"));
  for (const char* bad : {"\xFF", "\xC0\xAF", "\xE0\x80\xAF", "\xED\xA0\x80", "\xF4\x90\x80\x80",
                          "\xC3", "\xE2\x82"}) {
    EXPECT_FALSE(isValidUtf8(bad)) << bad;
  }
  EXPECT_ERROR(requireUtf8("\xFF", "the name"), "the name is not valid UTF-8");
}

// The file named `name` somewhere below `dir`.
fs::path findBelow(const fs::path& dir, const std::string& name) {
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.path().filename() == name) return e.path();
  }
  ADD_FAILURE() << "no " << name << " below " << dir;
  return dir / name;
}

// Every file below `dir`, checked to carry no markup in its name.
void expectSafeNames(const fs::path& dir) {
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(name.find_first_of("<>\"' "), std::string::npos) << e.path();
  }
}

TEST(ReportEscape, HostileSceneNamesReachReportsOnlyAsText) {
  TempDir dir("report_escape");
  writeGltfScene(dir.path() / "scenes" / (std::string(kHostile) + ".gltf"), makeClosedBoxScene());
  writeGltfScene(dir.path() / "scenes" / "b&\"'.gltf", makeSphericalCavityScene(1.0, 0.7));
  writeGltfScene(dir.path() / "scenes" / "plain.gltf", makeSphericalCavityScene(1.0, 0.4));
  SweepOptions s;
  s.scenes = {dir.path() / "scenes"};
  s.out = dir.path() / "sweep";
  s.spp = 16;  // enough distinct A values for fit's cubics
  s.width = s.height = 40;
  s.bounces = 1;
  s.specular_roughness = {0.4};
  s.specular_spp = 2;
  s.threads = 1;
  s.progress = false;
  runSweep(s);
  FitOptions f;
  f.sweep = s.out;
  f.out = dir.path() / "fit" / "fit.json";
  f.progress = false;
  runFit(f);
  ScreenAoOptions a;
  a.sweep = s.out;
  a.out = dir.path() / "screen_ao";
  a.threads = 1;
  a.progress = false;
  runScreenAo(a);
  const test::ExportFixture luts;
  luts.encode(luts.root.path() / "encode");
  ValidateGtsoOptions v;
  v.sweep = s.out;
  v.luts = luts.root.path();
  v.out = dir.path() / "validate";
  v.progress = false;
  runValidateGtso(v);
  for (const fs::path& page :
       {findBelow(dir.path() / "fit", "index.html"), findBelow(a.out, "screen_ao.html"),
        findBelow(v.out, "validate_gtso.html")}) {
    const std::string html = readBytes(page);
    EXPECT_EQ(html.find("<img src=x"), std::string::npos) << page;
    EXPECT_NE(html.find("&lt;img src=x onerror=alert(1)&gt;"), std::string::npos) << page;
    EXPECT_EQ(html.find("b&\""), std::string::npos) << page;
  }
  for (const fs::path& out : {s.out, dir.path() / "fit", a.out, v.out}) expectSafeNames(out);
}

}  // namespace
}  // namespace gtbake
