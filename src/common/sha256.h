// SHA-256 (FIPS 180-4, computed by OpenSSL's libcrypto) of a byte string, as 64 lower-case hex
// digits. Output-set manifests record it for every file so a reader can tell a file of the set
// from a stale or foreign one.
#pragma once

#include <string>
#include <string_view>

namespace gtbake {

std::string sha256Hex(std::string_view bytes);

}  // namespace gtbake
