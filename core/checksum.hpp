#pragma once
// Checksums of what slipfront writes and reads back (issue 18: checkpoints, the run files a study resumes
// from): XXH3-64 (xxHash, Debian's libxxhash), ~10 GB/s, so that verifying a file costs nothing next to
// reading it. Not a cryptographic hash: it detects corruption (truncation, flipped bits), not tampering.
#include <cstdint>
#include <string>
#include <string_view>

namespace slipfront::core {

/// XXH3-64 of the bytes.
std::uint64_t content_hash(std::string_view bytes);
/// The same as 16 lowercase hex digits (how files store it).
std::string content_hash_hex(std::string_view bytes);

}  // namespace slipfront::core
