// core/checksum.hpp: the checksum of checkpoints and run files (issue 18) is XXH3-64 as published.
#include <catch2/catch.hpp>

#include <string>

#include "core/checksum.hpp"

namespace core = slipfront::core;

TEST_CASE("checksum: XXH3-64 of the reference inputs, and every single-byte flip changes it", "[checksum]") {
  CHECK(core::content_hash("") == 0x2d06800538d394c2ull);  // xxHash's published XXH3_64bits("") (seed 0)
  CHECK(core::content_hash_hex("") == "2d06800538d394c2");
  std::string text(4096, '\0');
  for (std::size_t i = 0; i < text.size(); ++i) text[i] = static_cast<char>((i * 2654435761u) >> 13);
  const auto h = core::content_hash(text);
  int unchanged = 0;
  for (std::size_t i = 0; i < text.size(); i += 7) {
    std::string flipped = text;
    flipped[i] = static_cast<char>(flipped[i] ^ (1 << (i % 8)));
    unchanged += core::content_hash(flipped) == h;
  }
  CHECK(unchanged == 0);
}
