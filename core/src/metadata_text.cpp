// An asset's META chunk laid out for reading (ngi/metadata_text.h): one pass over the text,
// no parse tree, so nesting depth costs neither stack nor quadratic indentation.
#include "ngi/metadata_text.h"

#include <algorithm>

namespace ngi {

std::string indentedMetadata(std::string_view json, size_t maxDepth, size_t maxBytes)
{
    std::string out;
    size_t depth = 0, i = 0;
    auto newline = [&] {
        out += '\n';
        out.append(2 * std::min(depth, maxDepth), ' ');
    };
    // The next character that is not white space at or after `at`, or 0 at the end.
    auto nextToken = [&](size_t at) {
        while (at < json.size() && (json[at] == ' ' || json[at] == '\t' || json[at] == '\n' || json[at] == '\r')) ++at;
        return at < json.size() ? json[at] : '\0';
    };
    for (; i < json.size() && out.size() < maxBytes; ++i) {
        const char c = json[i];
        switch (c) {
        case ' ':
        case '\t':
        case '\n':
        case '\r': break;
        case '"': {
            const size_t start = i++;
            while (i < json.size() && json[i] != '"') i += json[i] == '\\' ? 2 : 1;
            out.append(json.substr(start, std::min(i, json.size() - 1) - start + 1));
            break;
        }
        case '{':
        case '[': {
            out += c;
            ++depth;
            const char next = nextToken(i + 1);
            if (next == '}' || next == ']') break;  // an empty object or array stays on its line
            newline();
            break;
        }
        case '}':
        case ']': {
            const bool empty = !out.empty() && (out.back() == '{' || out.back() == '[');
            depth = depth > 0 ? depth - 1 : 0;
            if (!empty) newline();
            out += c;
            break;
        }
        case ',':
            out += ',';
            newline();
            break;
        case ':': out += ": "; break;
        default: out += c;
        }
    }
    if (i < json.size()) out += "\n... (" + std::to_string(json.size() - i) + " more bytes of metadata not shown)";
    return out;
}

}  // namespace ngi
