#include "export/code_templates.h"

#include <algorithm>

#include "common/error.h"

namespace gtbake {
namespace {

bool isPlaceholderName(std::string_view name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

}  // namespace

std::string fillTemplate(std::string_view text, const TemplateValues& values) {
  std::vector<bool> used(values.size(), false);
  std::string out;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t open = text.find('@', pos);
    const std::size_t close = open == std::string_view::npos ? open : text.find('@', open + 1);
    if (close == std::string_view::npos) break;
    const std::string_view name = text.substr(open + 1, close - open - 1);
    if (!isPlaceholderName(name)) {  // a lone '@': copied, the next one may open a placeholder
      out.append(text.substr(pos, close - pos));
      pos = close;
      continue;
    }
    const auto it =
        std::find_if(values.begin(), values.end(), [&](const auto& v) { return v.first == name; });
    if (it == values.end()) {
      throw Error("internal: template placeholder @" + std::string(name) + "@ has no value");
    }
    used[static_cast<std::size_t>(it - values.begin())] = true;
    out.append(text.substr(pos, open - pos)).append(it->second);
    pos = close + 1;
  }
  out.append(text.substr(pos));
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!used[i]) throw Error("internal: no template placeholder @" + values[i].first + "@");
  }
  return out;
}

}  // namespace gtbake
