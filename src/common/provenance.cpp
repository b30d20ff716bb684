#include "common/provenance.h"

#include "common/error.h"

namespace gtbake {

void checkAttributes(const std::map<std::string, std::string>& attributes,
                     const std::map<std::string, std::string>& expected, const std::string& file,
                     const std::string& source) {
  for (const auto& [key, value] : expected) {
    const auto it = attributes.find(key);
    if (it == attributes.end()) {
      throw Error(file + ": has no " + key + " attribute; it was not written by this " + source +
                  "'s run");
    }
    if (it->second != value) {
      throw Error(file + ": " + key + " is '" + it->second + "' but " + source + " says '" + value +
                  "' (a file of another run or scene)");
    }
  }
}

}  // namespace gtbake
