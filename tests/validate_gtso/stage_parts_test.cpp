// Each part of validate-gtso says where it is (docs/validate_gtso.md §5): StageParts runs a part
// under a bar labelled "<stage>: <part>", passes its result through and records its wall seconds
// in order (validate_gtso.json /timings/parts); a disabled one prints nothing.
#include <gtest/gtest.h>

#include <string>

#include "common/progress.h"

namespace gtbake {
namespace {

TEST(StageParts, LabelsTimesAndPassesResultsThrough) {
  testing::internal::CaptureStderr();
  StageParts parts("validate-gtso", true);
  const int first = parts.run("first part", 2, [](Progress& bar) {
    bar.add(2);
    return 7;
  });
  const std::string second =
      parts.run("second part", 1, [](Progress&) { return std::string("x"); });
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(first, 7);
  EXPECT_EQ(second, "x");
  EXPECT_NE(err.find("validate-gtso: first part"), std::string::npos) << err;
  EXPECT_NE(err.find("validate-gtso: second part"), std::string::npos) << err;
  EXPECT_NE(err.find("done in"), std::string::npos) << err;
  ASSERT_EQ(parts.seconds().size(), 2u);
  EXPECT_EQ(parts.seconds()[0].first, "first part");
  EXPECT_EQ(parts.seconds()[1].first, "second part");
  EXPECT_GE(parts.seconds()[0].second, 0.0);

  testing::internal::CaptureStderr();
  StageParts quiet("validate-gtso", false);
  quiet.run("silent", 1, [](Progress&) { return 0; });
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  EXPECT_EQ(quiet.seconds().size(), 1u);
}

}  // namespace
}  // namespace gtbake
