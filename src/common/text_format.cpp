#include "common/text_format.h"

#include <cstdio>

namespace gtbake {

std::string formatNumber(double v, const char* format) {
  char text[64];
  std::snprintf(text, sizeof(text), format, v);
  return text;
}

std::string formatNumberList(const std::vector<double>& values, const char* empty) {
  if (values.empty()) return empty;
  std::string list;
  for (double v : values) list += (list.empty() ? "" : ",") + formatNumber(v, "%.9g");
  return list;
}

}  // namespace gtbake
