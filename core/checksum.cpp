#include "core/checksum.hpp"

#include <cstdio>

#include <xxhash.h>

namespace slipfront::core {

std::uint64_t content_hash(std::string_view bytes) { return XXH3_64bits(bytes.data(), bytes.size()); }

std::string content_hash_hex(std::string_view bytes) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(content_hash(bytes)));
  return buf;
}

}  // namespace slipfront::core
