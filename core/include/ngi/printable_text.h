// ngi core: text read from a file (an asset's source name, a network's name), made safe to
// print on a terminal: a crafted file must not reach the terminal with escape sequences.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace ngi {

// `text` with every byte that a terminal could act on written as \xNN (two lowercase hex
// digits): the C0 controls (ESC, BEL, CR, ...), DEL, the C1 controls U+0080..U+009F and every
// byte that is not part of well-formed UTF-8 (a lone 0x9b is a CSI on 8-bit terminals); a
// backslash is written \\ so that the result reads back unambiguously. Other UTF-8 (accented
// letters, CJK) passes unchanged.
inline std::string printableText(std::string_view text)
{
    std::string out;
    out.reserve(text.size());
    auto escape = [&](unsigned char byte) {
        char code[5];
        std::snprintf(code, sizeof code, "\\x%02x", unsigned(byte));
        out += code;
    };
    for (size_t i = 0; i < text.size();) {
        const auto byte = static_cast<unsigned char>(text[i]);
        if (byte == '\\') {
            out += "\\\\";
            ++i;
            continue;
        }
        if (byte < 0x80) {
            if (byte < 0x20 || byte == 0x7f)
                escape(byte);
            else
                out += char(byte);
            ++i;
            continue;
        }
        // The length of a well-formed UTF-8 sequence starting here (RFC 3629), 0 if none.
        size_t length = byte >= 0xc2 && byte <= 0xdf ? 2
            : byte >= 0xe0 && byte <= 0xef           ? 3
            : byte >= 0xf0 && byte <= 0xf4           ? 4
                                                     : 0;
        uint32_t codePoint = length == 2 ? byte & 0x1f : length == 3 ? byte & 0x0f : byte & 0x07;
        for (size_t k = 1; k < length; ++k) {
            const auto next = i + k < text.size() ? static_cast<unsigned char>(text[i + k]) : 0;
            if ((next & 0xc0) != 0x80) {
                length = 0;
                break;
            }
            codePoint = codePoint << 6 | (next & 0x3f);
        }
        const bool overlongOrInvalid =
            (length == 3 && (codePoint < 0x800 || (codePoint >= 0xd800 && codePoint <= 0xdfff))) ||
            (length == 4 && (codePoint < 0x10000 || codePoint > 0x10ffff));
        if (length == 0 || overlongOrInvalid || (codePoint >= 0x80 && codePoint <= 0x9f)) {
            escape(byte);
            ++i;
            continue;
        }
        out.append(text.substr(i, length));
        i += length;
    }
    return out;
}

}  // namespace ngi
