// ngi fuzz targets: what every harness shares. The fixups recompute the checksums a
// mutated input would otherwise fail at once, so the fuzzer reaches the parsing behind them.
#pragma once

#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <span>
#include <vector>

namespace ngi::fuzz {

inline uint32_t crc32Of(const uint8_t* data, size_t size)
{
    uLong crc = crc32(0L, Z_NULL, 0);
    while (size > 0) {  // zlib's length is a uInt
        const size_t n = size < (1u << 30) ? size : (1u << 30);
        crc = crc32(crc, data, uInt(n));
        data += n;
        size -= n;
    }
    return uint32_t(crc);
}

inline uint32_t load32(const uint8_t* p) { uint32_t v; std::memcpy(&v, p, 4); return v; }
inline uint64_t load64(const uint8_t* p) { uint64_t v; std::memcpy(&v, p, 8); return v; }
inline void store32(uint8_t* p, uint32_t v) { std::memcpy(p, &v, 4); }
inline void store64(uint8_t* p, uint64_t v) { std::memcpy(p, &v, 8); }

// An .ngi asset (asset.h's layout) with every chunk CRC and then the table CRC recomputed
// where the table and the chunk lie inside the input; other bytes are left as they are.
inline std::vector<uint8_t> withAssetChecksumsFixed(std::span<const uint8_t> input)
{
    constexpr size_t kHeader = 24, kEntry = 32;
    std::vector<uint8_t> b(input.begin(), input.end());
    if (b.size() < kHeader) return b;
    const uint64_t chunks = load32(&b[12]);
    const uint64_t entries = chunks < (b.size() - kHeader) / kEntry ? chunks : (b.size() - kHeader) / kEntry;
    for (uint64_t i = 0; i < entries; ++i) {
        uint8_t* e = &b[kHeader + i * kEntry];
        const uint64_t offset = load64(e + 8), size = load64(e + 16);
        if (offset <= b.size() && size <= b.size() - offset) store32(e + 24, crc32Of(b.data() + offset, size));
    }
    store32(&b[16], crc32Of(b.data() + kHeader, entries * kEntry));
    return b;
}

// An .ngiw weights file (network_weights.h's layout) with the body size and CRC recomputed.
inline std::vector<uint8_t> withWeightsChecksumsFixed(std::span<const uint8_t> input)
{
    constexpr size_t kHeader = 32;
    std::vector<uint8_t> b(input.begin(), input.end());
    if (b.size() < kHeader) return b;
    store64(&b[16], b.size() - kHeader);
    store32(&b[24], crc32Of(b.data() + kHeader, b.size() - kHeader));
    return b;
}

// A broken invariant the sanitizers cannot see: report it as a crash so the fuzzer keeps
// the input.
[[noreturn]] inline void invariantFailed(const char* what)
{
    std::fprintf(stderr, "ngi fuzz: invariant failed: %s\n", what);
    std::abort();
}

} // namespace ngi::fuzz
