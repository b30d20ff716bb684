// The bad-input contract of `gtbake screen-ao` as one check (docs/limits.md): the run throws one
// line holding `needle` and leaves no output set behind.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "common/error.h"
#include "screen_ao/screen_ao_command.h"

namespace gtbake::test {

inline void expectScreenAoError(const ScreenAoOptions& o, const std::string& needle) {
  try {
    runScreenAo(o);
    ADD_FAILURE() << "no error; expected " << needle;
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(needle), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  std::error_code ec;
  EXPECT_FALSE(std::filesystem::exists(o.out / "screen_ao.manifest.json", ec)) << needle;
}

}  // namespace gtbake::test
