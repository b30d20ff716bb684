// gtbake::Error: the one exception type that reaches the user.
//
// Its message is a single line that says what was wrong with the input and, where it helps, what
// to do instead. The CLI prints it as "gtbake: error: <message>" and exits with status 1. Anything
// else that escapes (std::bad_alloc, a library's own exception) is a bug or an environment failure
// and is reported as "gtbake: internal error: ...".
#pragma once

#include <stdexcept>
#include <string>

namespace gtbake {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace gtbake
