#include "core/base64.h"

#include <openssl/evp.h>

namespace acq {

std::string Base64Encode(const std::vector<std::uint8_t>& bytes) {
  std::string out(4 * ((bytes.size() + 2) / 3), '\0');
  const int n = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(out.data()), bytes.data(),
                                int(bytes.size()));
  out.resize(std::size_t(n));
  return out;
}

}  // namespace acq
