// ngi core: small command-line helpers shared by the tools (library code never parses argv).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

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

} // namespace ngi
