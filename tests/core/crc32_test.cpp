// The one CRC32 of the file formats (core/src/crc32.h): the standard check value, the empty
// input, and independence from how the bytes are split into zlib calls.
#include "crc32.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string_view>
#include <vector>

namespace {

std::span<const uint8_t> bytesOf(std::string_view s) { return {reinterpret_cast<const uint8_t*>(s.data()), s.size()}; }

TEST(Crc32, MatchesTheStandardCheckValue)
{
    // CRC-32/ISO-HDLC (zlib, PNG, gzip) of "123456789" is 0xCBF43926.
    EXPECT_EQ(ngi::detail::crc32Of(bytesOf("123456789")), 0xCBF43926u);
    EXPECT_EQ(ngi::detail::crc32Of(bytesOf("The quick brown fox jumps over the lazy dog")), 0x414FA339u);
}

TEST(Crc32, EmptyInputIsZero) { EXPECT_EQ(ngi::detail::crc32Of({}), 0u); }

TEST(Crc32, PieceSizeDoesNotChangeTheSum)
{
    std::vector<uint8_t> bytes(1000);
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = uint8_t(i * 7 + 3);
    const uint32_t whole = ngi::detail::crc32Of(bytes);
    for (size_t piece : {size_t(1), size_t(7), size_t(999), size_t(1000), size_t(4096)})
        EXPECT_EQ(ngi::detail::crc32Of(bytes, piece), whole) << "pieces of " << piece;
    EXPECT_EQ(ngi::detail::crc32Of(bytes, 0), whole);  // 0 is taken as 1, not an endless loop
}

TEST(Crc32, OneFlippedBitChangesTheSum)
{
    std::vector<uint8_t> bytes(64, 0x5a);
    const uint32_t before = ngi::detail::crc32Of(bytes);
    bytes[33] ^= 0x10;
    EXPECT_NE(ngi::detail::crc32Of(bytes), before);
}

}  // namespace
