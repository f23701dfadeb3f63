// CRC32 of a byte span through zlib, in pieces that fit zlib's uInt lengths.
#include "crc32.h"

#include <zlib.h>

#include <algorithm>

namespace ngi::detail {

uint32_t crc32Of(std::span<const uint8_t> bytes, size_t maxPiece)
{
    maxPiece = std::clamp<size_t>(maxPiece, 1, size_t(1) << 30);
    uLong crc = crc32(0L, Z_NULL, 0);
    for (size_t done = 0; done < bytes.size();) {
        const size_t n = std::min(bytes.size() - done, maxPiece);
        crc = crc32(crc, bytes.data() + done, uInt(n));
        done += n;
    }
    return uint32_t(crc);
}

}  // namespace ngi::detail
