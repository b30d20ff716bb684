// The code templates export fills (docs/export.md §5a): placeholders replaced by their
// values and nothing else touched, missing and unused values refused, and every embedded template
// filled without a placeholder left over.
#include <gtest/gtest.h>

#include <regex>

#include "common/error.h"
#include "export/code_templates.h"

namespace gtbake {
namespace {

TEST(CodeTemplates, FillsPlaceholdersAndLeavesOtherText) {
  EXPECT_EQ(fillTemplate("a @X@ b @Y_2@@X@.", {{"X", "1"}, {"Y_2", "@X@"}}), "a 1 b @X@1.");
  // A lone '@' or one around text that is no name stays as it is.
  EXPECT_EQ(fillTemplate("user@host x@y z @N@ @", {{"N", "n"}}), "user@host x@y z n @");
  EXPECT_EQ(fillTemplate("a@b c@N@", {{"N", "n"}}), "a@b cn");
  EXPECT_EQ(fillTemplate("", {}), "");
}

TEST(CodeTemplates, RefusesMissingAndUnusedValues) {
  EXPECT_THROW(fillTemplate("@MISSING@", {}), Error);
  EXPECT_THROW(fillTemplate("text", {{"UNUSED", "x"}}), Error);
}

// Each embedded template names placeholders (fillTemplate refuses one without a value, so none
// survives an export); the runtime sources, inserted as values, name none.
TEST(CodeTemplates, EmbeddedTemplatesHavePlaceholdersRuntimeHasNone) {
  const std::regex placeholder("@[A-Z0-9_]+@");
  for (const char* text :
       {kTablesHeaderTemplate, kProfilesHeaderTemplate, kProfileTablesHeaderTemplate,
        kTunedSettingsHeaderTemplate, kShaderIncludeTemplate, kMultiBounceShaderTemplate,
        kProfileTablesShaderTemplate, kMultiBounceTableShaderTemplate}) {
    EXPECT_TRUE(std::regex_search(text, placeholder)) << text;
  }
  EXPECT_FALSE(std::regex_search(kRuntimeLookupHeader, placeholder));
  EXPECT_FALSE(std::regex_search(kRuntimeLookupShader, placeholder));
  EXPECT_FALSE(std::regex_search(kRuntimeTableShader, placeholder));
  EXPECT_FALSE(std::regex_search(kRuntimeHlslMacros, placeholder));
  EXPECT_FALSE(std::regex_search(kRuntimeGlslMacros, placeholder));
}

}  // namespace
}  // namespace gtbake
