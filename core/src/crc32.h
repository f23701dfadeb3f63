// ngi core (private): the CRC32 (zlib's, polynomial 0xEDB88320, as in PNG and gzip) that
// guards the chunks of the asset format (asset.cpp) and the body of the network-weights
// format (network_weights.cpp). One definition, so both formats check the same sum.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace ngi::detail {

// CRC32 of `bytes` (0 for none). zlib takes 32-bit lengths, so the bytes are fed in pieces
// of at most `maxPiece` (> 0; the default suits any span, tests pass a small one to check
// that splitting does not change the sum).
uint32_t crc32Of(std::span<const uint8_t> bytes, size_t maxPiece = size_t(1) << 30);

}  // namespace ngi::detail
