#include "texture/texel_format.h"

namespace gtbake {

const char* texelFormatName(TexelFormat format) {
  switch (format) {
    case TexelFormat::kFloat32:
      return "float32";
    case TexelFormat::kBc4:
      return "bc4";
    case TexelFormat::kR16:
      return "r16";
    case TexelFormat::kR8:
      return "r8";
  }
  return "?";
}

}  // namespace gtbake
