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

inline uint32_t load32(const uint8_t* p)
{
    uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}
inline uint64_t load64(const uint8_t* p)
{
    uint64_t v;
    std::memcpy(&v, p, 8);
    return v;
}
inline void store32(uint8_t* p, uint32_t v) { std::memcpy(p, &v, 4); }
inline void store64(uint8_t* p, uint64_t v) { std::memcpy(p, &v, 8); }

// Format 5's POSI chunk (encoding 4, asset.h) in b[offset, offset + size): its rounds' CRC32s
// and the level table's CRC32 recomputed where the table parses (the chart count from HEAD,
// each chart header's length from its own level count), so mutations reach the level decoder.
inline void fixProgressivePositions(std::vector<uint8_t>& b, uint64_t offset, uint64_t size, uint32_t charts)
{
    uint8_t* p = b.data() + offset;
    uint64_t at = 2;
    if (size < 2 || charts > 1024) return;
    const uint32_t rounds = p[1];
    for (uint32_t c = 0; c < charts; ++c) {
        if (at + 2 >= size) return;
        at += 1 + 3 + 2 * uint64_t(p[at + 2]);  // flags, then version, levels, tangent scale, steps
    }
    std::vector<uint64_t> lengths(rounds);
    for (uint64_t& length : lengths) {
        length = 0;
        for (int shift = 0;; shift += 7) {
            if (at >= size || shift > 42) return;
            const uint8_t byte = p[at++];
            length |= uint64_t(byte & 0x7f) << shift;
            if (!(byte & 0x80)) break;
        }
    }
    const uint64_t crcs = at;
    if (size < crcs + 4 * uint64_t(rounds) + 4) return;
    uint64_t round = crcs + 4 * uint64_t(rounds) + 4;
    for (uint32_t r = 0; r < rounds; ++r) {
        if (lengths[r] > size - round) break;
        store32(p + crcs + 4 * r, crc32Of(p + round, lengths[r]));
        round += lengths[r];
    }
    const uint64_t covered = crcs + 4 * uint64_t(rounds);
    store32(p + covered, crc32Of(p, covered));
}

// An .ngi asset (asset.h's layout) with every chunk CRC and then the table CRC recomputed
// where the table and the chunk lie inside the input (format 5's POSI level table and levels
// first); other bytes are left as they are.
inline std::vector<uint8_t> withAssetChecksumsFixed(std::span<const uint8_t> input)
{
    constexpr size_t kHeader = 24, kEntry = 32;
    std::vector<uint8_t> b(input.begin(), input.end());
    if (b.size() < kHeader) return b;
    const uint64_t chunks = load32(&b[12]);
    const uint64_t entries = chunks < (b.size() - kHeader) / kEntry ? chunks : (b.size() - kHeader) / kEntry;
    auto inside = [&](const uint8_t* e) {
        const uint64_t offset = load64(e + 8), size = load64(e + 16);
        return offset <= b.size() && size <= b.size() - offset;
    };
    if (load32(&b[8]) >= 5) {
        uint32_t charts = 0;
        for (uint64_t i = 0; i < entries; ++i) {
            const uint8_t* e = &b[kHeader + i * kEntry];
            if (std::memcmp(e, "HEAD", 4) == 0 && inside(e) && load64(e + 16) >= 4) charts = load32(&b[load64(e + 8)]);
        }
        for (uint64_t i = 0; i < entries; ++i) {
            const uint8_t* e = &b[kHeader + i * kEntry];
            if (std::memcmp(e, "POSI", 4) == 0 && load32(e + 4) == 4 && inside(e))
                fixProgressivePositions(b, load64(e + 8), load64(e + 16), charts);
        }
    }
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

}  // namespace ngi::fuzz
