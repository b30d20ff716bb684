// The texel formats of the GTSO volumes, one enum for every stage: the shipped runtime header
// defines it (GtsoTexelFormat, runtime/gtso_runtime.h) because an engine's CPU code reads texels
// through it; gtbake code names it TexelFormat. docs/export.md "Texel formats".
#pragma once

#include "runtime/gtso_runtime.h"

namespace gtbake {

using TexelFormat = GtsoTexelFormat;  // kFloat32, kBc4 (BC4_UNORM), kR16, kR8 (UNORM)

// "float32", "bc4", "r16", "r8": the names of gtso.json, encode.json and the file suffixes.
const char* texelFormatName(TexelFormat format);

}  // namespace gtbake
