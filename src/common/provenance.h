// Checks that what a reader reads is what its provenance says it is: the string attributes a
// writer stamped into a file (EXR "gtbake.*" attributes) against the values the set's JSON
// records for it.
#pragma once

#include <map>
#include <string>

namespace gtbake {

// Throws gtbake::Error "<file>: attribute KEY is 'X' but <source> says 'Y' ..." for the first
// expected attribute that is missing or different.
void checkAttributes(const std::map<std::string, std::string>& attributes,
                     const std::map<std::string, std::string>& expected, const std::string& file,
                     const std::string& source);

}  // namespace gtbake
