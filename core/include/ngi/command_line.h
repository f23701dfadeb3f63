// ngi core: small command-line helpers shared by the tools (library code never parses argv).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <utility>

#include <glm/vec3.hpp>

namespace ngi {

// A bad command line: the tool prints the message and its usage and exits 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// `value` of option `flag` as a finite float; UsageError otherwise.
inline float parseFloatOption(const std::string& flag, const std::string& value)
{
    char* end = nullptr;
    const float f = std::strtof(value.c_str(), &end);
    if (value.empty() || *end || !std::isfinite(f)) throw UsageError(flag + " expects a number, got '" + value + "'");
    return f;
}

// `value` of option `flag` as a finite float in [lo, hi]; UsageError otherwise, saying
// "FLAG expects WHAT in [lo, hi]" (e.g. what = "degrees").
inline float parseFloatOptionInRange(const std::string& flag, const std::string& value, double lo, double hi,
                                     const std::string& what)
{
    const float f = parseFloatOption(flag, value);  // rejects text, nan and inf
    if (!(f >= lo && f <= hi)) {
        char range[64];
        std::snprintf(range, sizeof range, "[%g, %g]", lo, hi);
        throw UsageError(flag + " expects " + what + " in " + range + ", got '" + value + "'");
    }
    return f;
}

// `value` of option `flag` as an integer in [0, 2^20]; UsageError otherwise.
inline uint32_t parseUintOption(const std::string& flag, const std::string& value)
{
    char* end = nullptr;
    const unsigned long n = std::strtoul(value.c_str(), &end, 10);
    if (value.empty() || *end || value[0] == '-' || n > (1u << 20))
        throw UsageError(flag + " expects a non-negative integer, got '" + value + "'");
    return uint32_t(n);
}

// `value` of option `flag` as "X,Y,Z": three finite numbers; UsageError otherwise.
inline glm::vec3 parseVec3Option(const std::string& flag, const std::string& value)
{
    glm::vec3 v;
    size_t start = 0;
    for (int k = 0; k < 3; ++k) {
        const size_t comma = value.find(',', start);
        if ((k < 2) != (comma != std::string::npos))
            throw UsageError(flag + " expects three numbers X,Y,Z, got '" + value + "'");
        v[k] = parseFloatOption(flag, value.substr(start, k < 2 ? comma - start : std::string::npos));
        start = comma + 1;
    }
    return v;
}

// `value` of option `flag` as "WxH": two integers in [1, 2^20]; UsageError otherwise.
inline std::pair<uint32_t, uint32_t> parseSizeOption(const std::string& flag, const std::string& value)
{
    const size_t x = value.find('x');
    if (x == std::string::npos) throw UsageError(flag + " expects WxH, got '" + value + "'");
    const uint32_t width = parseUintOption(flag, value.substr(0, x)), height = parseUintOption(flag, value.substr(x + 1));
    if (width == 0 || height == 0) throw UsageError(flag + " must be positive, got '" + value + "'");
    return {width, height};
}

} // namespace ngi
