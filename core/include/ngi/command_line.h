// ngi core: small command-line helpers shared by the tools (library code never parses argv).
#pragma once

#include <cerrno>
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

// `value` of option `flag` as a decimal integer in [lo, hi]: digits only (no sign, no
// spaces), so "-1" is refused instead of wrapping to a huge count, and a value beyond `hi` (or
// beyond 64 bits) is refused instead of being truncated. UsageError otherwise:
// "FLAG expects an integer in [LO, HI], got 'VALUE'".
inline uint64_t parseIntegerOptionInRange(const std::string& flag, const std::string& value, uint64_t lo, uint64_t hi)
{
    bool digits = !value.empty() && value.size() <= 20;
    for (const char c : value) digits = digits && c >= '0' && c <= '9';
    uint64_t n = 0;
    if (digits) {
        errno = 0;
        n = std::strtoull(value.c_str(), nullptr, 10);
        digits = errno != ERANGE;
    }
    if (!digits || n < lo || n > hi)
        throw UsageError(flag + " expects an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                         "], got '" + value + "'");
    return n;
}

// `value` of option `flag` as an output path: UsageError "FLAG: the output path is empty" for
// "" (which would otherwise read as the option not given, or fail later as an internal error).
inline std::string parseOutputPathOption(const std::string& flag, const std::string& value)
{
    if (value.empty()) throw UsageError(flag + ": the output path is empty");
    return value;
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
    const uint32_t width = parseUintOption(flag, value.substr(0, x)),
                   height = parseUintOption(flag, value.substr(x + 1));
    if (width == 0 || height == 0) throw UsageError(flag + " must be positive, got '" + value + "'");
    return {width, height};
}

}  // namespace ngi
