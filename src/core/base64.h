// Base64 (RFC 4648, with padding) through OpenSSL: binary data in a JSON line (the live view's
// frame previews, daemon/control.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace acq {

std::string Base64Encode(const std::vector<std::uint8_t>& bytes);

}  // namespace acq
