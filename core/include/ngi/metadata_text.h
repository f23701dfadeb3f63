// ngi core: an asset's META chunk (JSON text from a file) laid out for reading, in time and
// space linear in its size whatever it holds.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace ngi {

// `json` indented two spaces per level, one member or element per line, like a JSON
// library's pretty dump, but bounded for hostile input: indentation stops growing past
// `maxDepth` levels (so deep nesting costs O(size * maxDepth), not O(size * depth)), and the
// text stops after `maxBytes` bytes with a last line saying how much of the metadata is left
// out. Strings are copied as they are, and text that is not JSON is laid out the same way
// (never an error): the result is for display only.
std::string indentedMetadata(std::string_view json, size_t maxDepth = 16, size_t maxBytes = size_t(64) << 10);

}  // namespace ngi
