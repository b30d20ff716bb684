// Text that crosses into another language: HTML/SVG reports, file names, JSON (docs/limits.md
// §Names in outputs). Every report escapes what it prints through escapeHtml, every file name
// made from a scene or user-given name goes through fileSlug, and every path written into JSON
// is valid UTF-8 (requireUtf8 refuses the others with one line).
#pragma once

#include <string>
#include <string_view>

namespace gtbake {

// `text` safe as HTML/SVG/XML element text and inside a quoted attribute: & < > " ' become
// character references; bytes that are not valid UTF-8 and control characters other than tab
// and line breaks become U+FFFD.
std::string escapeHtml(std::string_view text);

// A file-name-safe form of `name`: itself when it is made of [A-Za-z0-9_.-] only, does not start
// with '.' or '-' and has at most kMaxSlugLength bytes; otherwise the safe characters kept (others
// become '_', at most kMaxSlugLength of them, a '_' before a leading '.' or '-') and "-" plus the
// first 8 hex digits of the name's SHA-256, so distinct names give distinct slugs and the same name
// always the same slug.
std::string fileSlug(std::string_view name);
inline constexpr std::size_t kMaxSlugLength = 64;

// True when `text` is well-formed UTF-8 (no overlong forms, surrogates or code points above
// U+10FFFF).
bool isValidUtf8(std::string_view text);

// Throws gtbake::Error "<what> is not valid UTF-8 ..." unless isValidUtf8(text).
void requireUtf8(std::string_view text, const std::string& what);

}  // namespace gtbake
