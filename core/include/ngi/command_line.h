// ngi core: the argv reader and the option value parsers shared by the tools (library code never parses argv).
#pragma once

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

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

// `value` of option `flag` as a count in [0, 2^20]: parseIntegerOptionInRange with that range
// (its digits-only rule and its message).
inline uint32_t parseUintOption(const std::string& flag, const std::string& value)
{
    return uint32_t(parseIntegerOptionInRange(flag, value, 0, 1u << 20));
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

// Reads a tool's arguments one at a time, the same way in every tool:
//
//   ngi::ArgReader args(argc, argv);
//   while (args.next()) {
//       if (args.is("--size")) size = ngi::parseSizeOption(args.flag(), args.value());
//       else if (args.is("--json")) json = true;
//       else if (args.positional()) paths.push_back(args.flag());
//       else throw args.unknown();
//   }
//
// An argument is an option when it starts with '-' (except "-" alone, and "" is positional);
// the first "--" is skipped and makes every later argument positional. An option's value is
// the argument after it, whatever it looks like ("--eye -1,0,0").
class ArgReader {
public:
    // The arguments argv[first], ..., argv[argc - 1] (argv[0], the program, skipped by default).
    ArgReader(int argc, const char* const* argv, int first = 1) : arguments_(argv + std::min(first, argc), argv + argc)
    {}

    // The arguments `arguments` (e.g. a subcommand's, those after its name).
    explicit ArgReader(std::vector<std::string> arguments) : arguments_(std::move(arguments)) {}

    // Moves to the next argument, past the current option's value if value() took it and past
    // the first "--"; false when none is left.
    bool next()
    {
        at_ += valueTaken_ ? 2 : 1;
        valueTaken_ = false;
        if (at_ < arguments_.size() && !afterDashes_ && arguments_[at_] == "--") {
            afterDashes_ = true;
            ++at_;
        }
        return at_ < arguments_.size();
    }

    // The current argument as given: the option's name, or the positional argument.
    const std::string& flag() const { return arguments_.at(at_); }

    // Whether the current argument is the option `name` (or `alias`, e.g. "-o" and "--output").
    bool is(std::string_view name, std::string_view alias = {}) const
    {
        return !positional() && (flag() == name || (!alias.empty() && flag() == alias));
    }

    // The argument after the current option, taken as its value whatever it looks like;
    // UsageError "FLAG expects a value" when the option is the last argument. flag() still
    // names the option (so `parse(args.flag(), args.value())` reads right in either order).
    const std::string& value()
    {
        if (at_ + 1 >= arguments_.size()) throw UsageError(flag() + " expects a value");
        valueTaken_ = true;
        return arguments_[at_ + 1];
    }

    // Whether the current argument is positional: not an option, or after "--".
    bool positional() const
    {
        const std::string& a = flag();
        return afterDashes_ || a.size() < 2 || a[0] != '-';
    }

    // The error to throw for a current argument that the tool does not take: UsageError
    // "unknown option FLAG" for an option, "unexpected argument ARG" for a positional one.
    UsageError unknown() const
    {
        return UsageError((positional() ? "unexpected argument " : "unknown option ") + flag());
    }

private:
    std::vector<std::string> arguments_;
    size_t at_ = size_t(-1);   // the current argument; next() moves to the first
    bool valueTaken_ = false;  // value() took arguments_[at_ + 1]
    bool afterDashes_ = false;
};

}  // namespace ngi
