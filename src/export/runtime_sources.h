// The runtime source templates of src/runtime/ as text (generated at configure time):
// gtso_runtime.h (the C++ lookup code the header ships) and gtso_runtime.shader (its HLSL/GLSL
// port). See docs/export.md "Header contents".
#pragma once

namespace gtbake {

extern const char* const kRuntimeLookupHeader;
extern const char* const kRuntimeLookupShader;

}  // namespace gtbake
