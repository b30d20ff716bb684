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
  // Control characters (a line break from a quoted input above all) become '?', so the message
  // is one line whatever file text or argument it quotes (docs/limits.md).
  explicit Error(const std::string& message) : std::runtime_error(oneLine(message)) {}

 private:
  static std::string oneLine(std::string text) {
    for (char& c : text) c = (c >= 0 && c < 0x20) || c == 0x7f ? '?' : c;
    return text;
  }
};

}  // namespace gtbake
