// ngi offline: the helpers the mesh readers share (messages, lines, numbers, colours).
#include "mesh_io_internal.h"

#include "ngi/error.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace ngi::mesh_io {

void fail(const Input& input, const std::string& problem) { throw Error(input.name + ": " + problem); }

LineReader::LineReader(const Input& input, size_t offset) : input_(input), text_(input.text()), at_(offset)
{
    if (const void* nul = at_ < text_.size() ? std::memchr(text_.data() + at_, 0, text_.size() - at_) : nullptr)
        fail(input_,
             "not a text file (NUL byte at offset " + std::to_string(static_cast<const char*>(nul) - text_.data()) +
                 ")");
}

bool LineReader::next(std::string_view& line)
{
    if (at_ >= text_.size()) return false;
    size_t end = text_.find('\n', at_);
    if (end == std::string_view::npos) end = text_.size();
    line = text_.substr(at_, end - at_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    at_ = end + 1;
    ++line_;
    return true;
}

std::string_view nextToken(std::string_view& rest)
{
    size_t begin = 0;
    while (begin < rest.size() &&
           (rest[begin] == ' ' || rest[begin] == '\t' || rest[begin] == '\r' || rest[begin] == '\f' ||
            rest[begin] == '\v'))
        ++begin;
    size_t end = begin;
    while (end < rest.size() &&
           !(rest[end] == ' ' || rest[end] == '\t' || rest[end] == '\r' || rest[end] == '\f' || rest[end] == '\v'))
        ++end;
    std::string_view token = rest.substr(begin, end - begin);
    rest.remove_prefix(end);
    return token;
}

bool parseDouble(std::string_view token, double& value)
{
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty() || token.front() == '+') return false;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (end != token.data() + token.size()) return false;
    // Out of double range (1e400, 1e-400): from_chars gives no value; strtod gives the
    // infinity or zero, which the callers judge like any other value.
    if (ec == std::errc::result_out_of_range)
        value = std::strtod(std::string(token).c_str(), nullptr);
    else if (ec != std::errc())
        return false;
    return true;
}

bool parseInteger(std::string_view token, long long& value)
{
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    return !token.empty() && ec == std::errc() && end == token.data() + token.size();
}

bool parseUnsigned(std::string_view token, uint64_t& value)
{
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    return !token.empty() && ec == std::errc() && end == token.data() + token.size();
}

bool usableCoordinate(double value)
{
    return std::isfinite(value) && std::fabs(value) <= double(std::numeric_limits<float>::max());
}

std::string coordinateProblem(std::string_view token, double value)
{
    return "non-finite coordinate '" + std::string(token.substr(0, 40)) + "'" +
        (std::isfinite(value) ? " (beyond single precision)" : "");
}

}  // namespace ngi::mesh_io
