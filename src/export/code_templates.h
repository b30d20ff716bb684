// The code templates `gtbake export` fills (docs/export.md §5a): the runtime sources of
// src/runtime/ (gtso_runtime.h, the C++ lookup the header ships; gtso_runtime.shader, its
// HLSL/GLSL port) and the templates of src/export/templates/, embedded as text at configure time
// (embedded_templates.cpp.in), and the function that fills a template's @NAME@ placeholders.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gtbake {

extern const char* const kRuntimeLookupHeader;  // src/runtime/gtso_runtime.h
extern const char* const kRuntimeLookupShader;  // src/runtime/gtso_runtime.shader
extern const char* const kRuntimeTableShader;   // src/runtime/multibounce_table.shader
// src/runtime/gtso_language.hlsl / .glsl: the language macros gtso_runtime.shader needs.
extern const char* const kRuntimeHlslMacros;
extern const char* const kRuntimeGlslMacros;
// src/export/templates/:
extern const char* const kTablesHeaderTemplate;         // gtbake_tables.h.in
extern const char* const kProfilesHeaderTemplate;       // profiles.h.in
extern const char* const kProfileTablesHeaderTemplate;  // profile_tables.h.in
extern const char* const kTunedSettingsHeaderTemplate;  // tuned_settings.h.in
extern const char* const kShaderIncludeTemplate;        // gtbake_tables.shader.in
extern const char* const kMultiBounceShaderTemplate;    // multibounce.shader.in
// profile_tables.shader.in has no final line break: its last placeholder ends the last line.
extern const char* const kProfileTablesShaderTemplate;     // profile_tables.shader.in
extern const char* const kMultiBounceTableShaderTemplate;  // multibounce_table.shader.in

// A placeholder's name (without the @s) and the text that replaces it.
using TemplateValues = std::vector<std::pair<std::string, std::string>>;

// `text` with every placeholder @NAME@ (NAME: capitals, digits and '_') replaced by its value;
// the values are inserted as they are, never scanned again. Any other '@' stays. Throws Error on
// a placeholder without a value and on a value no placeholder uses.
std::string fillTemplate(std::string_view text, const TemplateValues& values);

}  // namespace gtbake
