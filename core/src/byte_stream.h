// ngi core (private): little-endian byte writer and bounds-checked reader shared by the
// asset (asset.cpp) and network-weights (network_weights.cpp) file formats.
#pragma once

#include "ngi/error.h"

#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

namespace ngi::detail {

struct ByteWriter {
    std::vector<uint8_t> bytes;
    template <class T> void put(T v)
    {
        const size_t at = bytes.size();
        bytes.resize(at + sizeof(T));
        std::memcpy(bytes.data() + at, &v, sizeof(T));
    }
    // u32 length, then the bytes.
    void putString(const std::string& s)
    {
        put<uint32_t>(uint32_t(s.size()));
        bytes.insert(bytes.end(), s.begin(), s.end());
    }
};

// Appends v as LEB128: 7 bits per byte, low first, the high bit set on all but the last.
inline void putLeb128(std::vector<uint8_t>& out, uint64_t v)
{
    do {
        const uint8_t low = uint8_t(v & 0x7f);
        v >>= 7;
        out.push_back(uint8_t(low | (v ? 0x80 : 0)));
    } while (v);
}

// Reads from `bytes`; every failure is one ngi::Error "NAME: problem".
struct ByteReader {
    std::span<const uint8_t> bytes;
    size_t at = 0;
    const std::string& name;
    [[noreturn]] void fail(const std::string& problem) const { throw Error(name + ": " + problem); }
    template <class T> T get(const char* what)
    {
        if (bytes.size() - at < sizeof(T)) fail(std::string(what) + " is truncated");
        T v;
        std::memcpy(&v, bytes.data() + at, sizeof(T));
        at += sizeof(T);
        return v;
    }
    std::string getString(const char* what, size_t maxLength)
    {
        const uint32_t n = get<uint32_t>(what);
        if (n > maxLength || bytes.size() - at < n) fail(std::string(what) + " is truncated or too long");
        std::string s(reinterpret_cast<const char*>(bytes.data() + at), n);
        at += n;
        return s;
    }
};

}  // namespace ngi::detail
